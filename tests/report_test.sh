#!/usr/bin/env bash
# `omnishadow report` in a real browser: a small run and a synthetic history of it (24 commits, one case 15%
# slower from the seventeenth on) make one HTML page; headless Chromium loads it, every case id must be in the page,
# the history must name the slowed case's step, and a screenshot is taken (OMNISHADOW_REPORT_SCREENSHOT=FILE keeps
# it, e.g. docs/report.png). Skipped (exit 77) only where Chromium or OpenGL is missing, saying which.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
browser="$(command -v chromium || command -v chromium-browser || true)"
if [ -z "$browser" ]; then
  echo "report test skipped: no chromium on PATH (Debian package chromium; scripts/setup.sh installs it)"
  exit 77
fi
if reason="$("$bin" list | grep -m1 'gl: unavailable')"; then
  echo "report test skipped: OpenGL backend unavailable here: $reason"
  exit 77
fi
tmp="$(mktemp -d)"
trap '[ -n "${KEEP:-}" ] || rm -rf "$tmp"' EXIT
"$bin" run --backend gl --scene room --cube 64 --frame 160x120 --technique six_pass,geometry_shader \
  --filter hard,pcf_disk20 --frames 2 --warmup 0 --light-radius 0 --out "$tmp/run" --benchmark_repetitions=3 \
  >"$tmp/run.log" 2>&1 || { cat "$tmp/run.log"; exit 1; }
/usr/bin/python3 - "$tmp" <<'PY'
import copy, json, os, random, sys
tmp = sys.argv[1]
doc = json.load(open(f"{tmp}/run/results.json"))
slowed = doc["omnishadow"]["cases"][0]["id"]
for i in range(24):
    d = copy.deepcopy(doc)
    d["omnishadow"]["commit"] = f"c{i:02d}"
    d["omnishadow"]["commit_date"] = f"2026-11-{i + 1:02d}T00:00:00+00:00"
    for c in d["omnishadow"]["cases"]:
        per = c.get("timing", {}).get("per_repetition", {})
        wobble = random.Random(i).gauss(1.0, 0.01)
        per["frame_ms"] = [v * wobble * (1.15 if c["id"] == slowed and i >= 16 else 1.0) for v in per.get("frame_ms", [])]
    os.makedirs(f"{tmp}/history/r{i:02d}")
    json.dump(d, open(f"{tmp}/history/r{i:02d}/results.json", "w"))
open(f"{tmp}/slowed", "w").write(slowed)
PY
"$bin" report "$tmp/run" --history "$tmp/history" --out "$tmp/report.html" >/dev/null
"$browser" --headless=new --no-sandbox --disable-gpu --dump-dom "file://$tmp/report.html" 2>/dev/null >"$tmp/dom.html"
/usr/bin/python3 - "$tmp" <<'PY'
import html, json, sys
tmp = sys.argv[1]
dom = html.unescape(open(f"{tmp}/dom.html").read())
ids = [c["id"] for c in json.load(open(f"{tmp}/run/results.json"))["omnishadow"]["cases"]]
missing = [i for i in ids if i not in dom]
assert not missing, f"case ids missing from the rendered page: {missing}"
assert "at c16" in dom, "the history step at c16 is not shown"
assert dom.count("data:image/png;base64,") >= 3, "charts are not embedded"
assert "http://" not in dom and "https://" not in dom, "the page must not reach the network"
answer = dom.find("<h2>The answer</h2>")
assert 0 <= answer < dom.find("<h2>Status</h2>"), "the answer comes before the statuses and the detail"
assert "Fastest shadow pass: " in dom and "Pareto set: <code>" in dom, "the answer names the fastest and the front"
# The speed/accuracy chart is inline SVG: every case a point whose hover tooltip names it.
tips = [i for i in ids if f"<title>{i}: " in dom]
assert len(tips) == len(ids), f"cases without a hover tooltip on the chart: {set(ids) - set(tips)}"
assert "Pareto front of each backend/scene</text>" in dom, "the legend's title is whole"
print(f"report: {len(ids)} cases present in the page Chromium rendered")
PY
# The case table filters as one types, and from the page's #fragment: half the cases are pcf_disk20.
"$browser" --headless=new --no-sandbox --disable-gpu --dump-dom "file://$tmp/report.html#pcf_disk20" 2>/dev/null \
  >"$tmp/filtered.html"
grep -q "2 of 4 cases" "$tmp/filtered.html" || { echo "the case filter did not leave 2 of 4 cases"; exit 1; }
# A run that is not whole says so first: stopped, with a shard missing.
/usr/bin/python3 - "$tmp" <<'PY'
import json, os, sys
tmp = sys.argv[1]
doc = json.load(open(f"{tmp}/run/results.json"))
doc["omnishadow"].update({"complete": False, "stopped_by": "SIGINT", "missing_shards": [1]})
doc["omnishadow"]["cases"][-1]["status"] = "interrupted"
os.makedirs(f"{tmp}/stopped")
json.dump(doc, open(f"{tmp}/stopped/results.json", "w"))
PY
"$bin" report "$tmp/stopped" --out "$tmp/stopped.html" >/dev/null
"$browser" --headless=new --no-sandbox --disable-gpu --dump-dom "file://$tmp/stopped.html" 2>/dev/null >"$tmp/stopped_dom.html"
/usr/bin/python3 - "$tmp" <<'PY'
import html, sys
tmp = sys.argv[1]
dom = html.unescape(open(f"{tmp}/stopped_dom.html").read())
at = dom.find("Incomplete run: stopped by SIGINT; shard 1 missing. 1 case(s) were never timed")
assert at >= 0, "the stopped run's banner is missing"
assert at < dom.find("<h2>"), "the banner comes before every section"
whole = html.unescape(open(f"{tmp}/dom.html").read())
assert "Incomplete run" not in whole, "a whole run shows no banner"
assert "every check passed" in whole, "the small run's checks all passed"
PY
# A run whose cases ran no check (every one unsupported) does not say that every check passed.
/usr/bin/python3 - "$tmp" <<'PY'
import json, os, sys
tmp = sys.argv[1]
doc = json.load(open(f"{tmp}/run/results.json"))
for c in doc["omnishadow"]["cases"]:
    c.update({"status": "unsupported", "checks": []})
    c.pop("timing", None)
doc["benchmarks"] = []
os.makedirs(f"{tmp}/unchecked")
json.dump(doc, open(f"{tmp}/unchecked/results.json", "w"))
PY
"$bin" report "$tmp/unchecked" --out "$tmp/unchecked.html" >/dev/null
grep -q "no check ran in this run" "$tmp/unchecked.html" || { echo "a run with no check says every check passed"; exit 1; }
if grep -q "every check passed" "$tmp/unchecked.html"; then echo "a run with no check says every check passed"; exit 1; fi
"$browser" --headless=new --no-sandbox --disable-gpu --window-size=1280,2400 --screenshot="$tmp/report.png" \
  "file://$tmp/report.html" >/dev/null 2>&1
test -s "$tmp/report.png"
if [ -n "${OMNISHADOW_REPORT_SCREENSHOT:-}" ]; then cp "$tmp/report.png" "$OMNISHADOW_REPORT_SCREENSHOT"; fi
# A run over several light counts gets the many-light section: a line per case through its counts and the table;
# the one-count run above says it has one.
"$bin" run --backend gl --scene hall --light-count 1,2 --layout cube_array --cube 32 --frame 96x64 \
  --technique six_pass --filter hard --frames 2 --warmup 0 --light-radius 0 --max-error 100 --check \
  --out "$tmp/lights" --benchmark_repetitions=1 >"$tmp/lights.log" 2>&1 || { cat "$tmp/lights.log"; exit 1; }
"$bin" report "$tmp/lights" --out "$tmp/lights.html" >/dev/null
"$browser" --headless=new --no-sandbox --disable-gpu --dump-dom "file://$tmp/lights.html" >"$tmp/lights_dom.html" \
  2>/dev/null
/usr/bin/python3 - "$tmp" <<'PY'
import html, sys
tmp = sys.argv[1]
dom = html.unescape(open(f"{tmp}/lights_dom.html").read())
section = dom[dom.find("<h2>Many lights</h2>"):]
assert "<polyline" in section and "<th>2 lights</th>" in section, "the many-light chart and table are missing"
assert "gl/hall/c32/hard/cube_array/six_pass" in section, "the many-light row names its case"
assert "one light count in this run" in html.unescape(open(f"{tmp}/dom.html").read()), "a one-count run says so"
PY
