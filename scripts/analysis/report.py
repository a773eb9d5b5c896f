#!/usr/bin/python3
"""One self-contained HTML page for a run (and, with --history, its history): what a person reads after CI.

No network: styles inline, charts rendered by matplotlib and embedded as PNG data, failed checks' diff images
embedded from the run folder, one inline script (the case table's filter). Sections: a banner for a run that is
not whole; the device (renderer, driver, clocks) and commit; the answer (report_answer.py); status counts; the
shadow pass per technique against six_pass and the lighting pass per filter against hard (charts and tables);
speed against accuracy with the Pareto front; many lights (report_lights.py: frame time per light and error
against the light count, for a run with several); every failed check with its diff image; with --history, a small
time series per case (median per commit, the band between the lowest and highest repetition, change points
marked), regressions first; and every case with its status and figures.

Usage: scripts/analysis/report.py RUN [--history RUN_OR_FOLDER...] [--out FILE]   (omnishadow report calls it)
"""
import argparse
import base64
import io
import json
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
import history  # noqa: E402
from results_io import load_results, write_text_atomic  # noqa: E402
from report_answer import answer_section  # noqa: E402
from report_lights import lights_section  # noqa: E402
from report_svg import tradeoff_svg  # noqa: E402
from report_util import esc, pass_ms  # noqa: E402

STYLE = """body{font:14px/1.45 system-ui,sans-serif;margin:24px auto;max-width:1180px;color:#1d1d1f}
h1{font-size:22px}h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}
table{border-collapse:collapse;margin:8px 0;font-size:12.5px}td,th{border:1px solid #ddd;padding:3px 7px;text-align:left}
th{background:#f4f4f6}code{font-size:12px}.ok{color:#17702f}.bad{color:#b3261e;font-weight:600}
.grid{display:flex;flex-wrap:wrap;gap:10px}.card{border:1px solid #ddd;padding:6px;border-radius:4px}
img{max-width:100%}.small{color:#666;font-size:12px}
.incomplete{background:#fdecea;border:2px solid #b3261e;color:#b3261e;padding:8px 12px;font-weight:600}"""


def png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode()


def embed(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode()


def header(doc):
    o = doc["omnishadow"]
    rows = [("commit", o.get("commit", "?")), ("commit date", o.get("commit_date", "")),
            ("command", o.get("command_line", ""))]
    for backend, d in sorted(o.get("devices", {}).items()):
        rows.append((backend, f"{d.get('renderer', '')} | {d.get('version', '')} | {d.get('platform', '')}"))
    clocks = [s.get("clock_mhz") for c in o.get("cases", []) for s in c.get("device_state", {}).get("samples", [])
              if s.get("clock_mhz")]
    if clocks:
        rows.append(("clocks", f"{min(clocks):.0f}-{max(clocks):.0f} MHz over "
                               f"{len(clocks)} samples ({o['cases'][0].get('device_state', {}).get('source', '')})"))
    phases = o.get("phases", {})
    if phases.get("timed_seconds"):
        rows.append(("run", f"{phases['untimed_seconds']:.1f} s untimed + {phases['timed_seconds']:.1f} s timed"))
    return "<table>" + "".join(f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in rows) + "</table>"


def incomplete_banner(doc):
    """The first thing on the page of a run that is not whole: stopped, shards missing, or merged from parts that
    were; empty for a whole run."""
    o = doc["omnishadow"]
    if o.get("complete", False):
        return ""
    why = []
    if o.get("stopped_by"):
        why.append(f"stopped by {o['stopped_by']}")
    if o.get("missing_shards"):
        why.append("shard " + ", ".join(str(s) for s in o["missing_shards"]) + " missing")
    if not why:
        why.append("the run did not end (complete: false)")
    untimed = sum(1 for c in o.get("cases", []) if c.get("status") == "interrupted")
    return (f"<p class='incomplete'>Incomplete run: {esc('; '.join(why))}. {untimed} case(s) were never timed "
            f"(interrupted); the figures below are of what ran, and cases it lacks are missing.</p>")


def status_counts(cases):
    counts = {}
    for c in cases:
        counts[c["status"]] = counts.get(c["status"], 0) + 1
    return " &middot; ".join(f"<span class='{'ok' if s == 'ok' else 'bad'}'>{esc(s)}: {n}</span>"
                             for s, n in sorted(counts.items()))


def ratio_chart(cases, axis, base, pass_name, title):
    """Grouped bars: per (backend, scene, cube) the median pass time of each axis value over the base value's."""
    groups = {}
    for c in cases:
        ms = pass_ms(c, pass_name)
        if ms is None:
            continue
        a = c["axes"]
        key = f"{a['backend']}/{a['scene']}/c{a['cube_size']}"
        groups.setdefault(key, {}).setdefault(a[axis], []).append(ms)
    if not groups:
        return "<p class='small'>no timed cases</p>"
    values = sorted({v for g in groups.values() for v in g}, key=lambda v: (v != base, v))
    fig, ax = plt.subplots(figsize=(max(6, 1.4 * len(groups)), 3.2))
    width = 0.8 / len(values)
    rows = []
    for i, (key, g) in enumerate(sorted(groups.items())):
        ref = statistics.median(g[base]) if base in g else None
        for j, v in enumerate(values):
            if v in g and ref:
                ax.bar(i + j * width, statistics.median(g[v]) / ref, width, label=v if i == 0 else None,
                       color=plt.cm.tab10(j))
        rows.append(f"<tr><td><code>{esc(key)}</code></td>" + "".join(
            f"<td>{statistics.median(g[v]):.3f} ms" + (f" ({statistics.median(g[v]) / ref:.2f}x)" if ref else "")
            + "</td>" if v in g else "<td>-</td>" for v in values) + "</tr>")
    ax.axhline(1.0, color="#999", lw=0.8)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(groups))], sorted(groups), rotation=20, fontsize=7)
    ax.set_ylabel(f"x {base}")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    table = "<table><tr><th>group</th>" + "".join(f"<th>{esc(v)}</th>" for v in values) + "</tr>" + "".join(rows)
    return f"<img src='{png(fig)}' alt='{esc(title)}'>" + table + "</table>"


def failed_checks(doc, run_dir):
    # A run whose cases ran no check (all unsupported, or crashed before their checks) has nothing that passed.
    if not any(c.get("checks") for c in doc["omnishadow"]["cases"]):
        return "<p>no check ran in this run</p>"
    out = []
    for c in doc["omnishadow"]["cases"]:
        for check in c.get("checks", []):
            if check.get("passed", True):
                continue
            img = check.get("diff_image")
            path = os.path.join(run_dir, img) if img else None
            pic = f"<img src='{embed(path)}' alt='diff'>" if path and os.path.exists(path) else "(no diff image)"
            out.append(f"<div class='card'><b class='bad'>{esc(check['name'])}</b> <code>{esc(c['id'])}</code> "
                       f"against <code>{esc(check.get('against', ''))}</code>: "
                       f"{check.get('percent_differing', 0):.4g}% differ, max {check.get('max_abs_difference', 0):.4g}"
                       f"<br>{pic}</div>")
    return "<div class='grid'>" + "".join(out) + "</div>" if out else "<p class='ok'>every check passed</p>"


def history_section(paths):
    result = history.analyse(history.find_runs(paths), history.load_accepted(
        os.path.join(history.ROOT, "results", "accepted_steps.json")), history.ROOT)
    alerted = {(a["case"], "frame_ms"): a for a in result["alerts"] if a["metric"] == "frame_ms"}
    series = {}
    for run in history.find_runs(paths):
        doc = history.load(run)
        if history.device_key(doc) != result["device_key"]:
            continue
        date_commit = history.commit_order([doc], history.ROOT)[0]
        for c in doc["omnishadow"].get("cases", []):
            per = c.get("timing", {}).get("per_repetition", {}).get("frame_ms") or []
            if per:
                series.setdefault(c["id"], []).append((date_commit, statistics.median(per), min(per), max(per)))
    order = sorted(series, key=lambda cid: (not alerted.get((cid, "frame_ms"), {}).get("regression", False),
                                            (cid, "frame_ms") not in alerted, cid))
    cards = []
    for cid in order:
        pts = sorted(series[cid])
        fig, ax = plt.subplots(figsize=(3.6, 1.6))
        x = range(len(pts))
        ax.fill_between(x, [p[2] for p in pts], [p[3] for p in pts], color="#c9d7f2", lw=0)
        ax.plot(x, [p[1] for p in pts], color="#1f4e9c", lw=1)
        a = alerted.get((cid, "frame_ms"))
        if a:
            commits = [p[0][1] for p in pts]
            if a["commit"] in commits:
                ax.axvline(commits.index(a["commit"]) - 0.5, color="#b3261e", lw=1.2)
        ax.set_xticks([])
        ax.tick_params(labelsize=6)
        flag = (f"<span class='bad'>{100 * a['step']:+.1f}% at {esc(a['commit'])}</span>" if a else "")
        cards.append(f"<div class='card'><code>{esc(cid)}</code> {flag}<br><img src='{png(fig)}' alt='history'></div>")
    alerts = "".join(f"<li><code>{esc(a['case'])}</code> {esc(a['metric'])}: {100 * a['step']:+.1f}% at "
                     f"{esc(a['commit'])}</li>" for a in result["alerts"])
    return (f"<p>{result['runs']} runs over {len(result['commits'])} commits; {len(result['alerts'])} alerts "
            f"(regressions first)</p><ul>{alerts}</ul><div class='grid'>{''.join(cards)}</div>")


def case_table(cases):
    def fmt(v, digits=3):
        return "" if v is None else f"{v:.{digits}f}"
    rows = []
    for c in cases:
        acc = c.get("accuracy", {}).get("misclassified_percent")
        status = "ok" if c["status"] == "ok" else "bad"
        rows.append(f"<tr id='{esc(c['id'])}'><td><code>{esc(c['id'])}</code></td>"
                    f"<td class='{status}'>{esc(c['status'])}</td><td>{fmt(pass_ms(c, 'shadow'))}</td>"
                    f"<td>{fmt(pass_ms(c, 'lighting'))}</td><td>{fmt(acc)}</td><td>{esc(c.get('reason', ''))}</td></tr>")
    return ("<p><input id='case-filter' size='60' placeholder='show cases whose id has every word: gl pcf_disk20'> "
            "<span id='case-count' class='small'></span></p>"
            "<table id='cases'><tr><th>case</th><th>status</th><th>shadow ms</th><th>lighting ms</th>"
            "<th>misclassified %</th><th>reason</th></tr>" + "".join(rows) + "</table>" + CASE_FILTER_SCRIPT)


# Filters the case table as one types (and from the page's #fragment, so a link can carry a filter); no network.
CASE_FILTER_SCRIPT = """<script>
(function () {
  var box = document.getElementById('case-filter'), rows = document.querySelectorAll('#cases tr[id]');
  function apply() {
    var words = box.value.toLowerCase().split(/\\s+/).filter(Boolean), shown = 0;
    rows.forEach(function (r) {
      var id = r.id.toLowerCase(), keep = words.every(function (w) { return id.indexOf(w) >= 0; });
      r.style.display = keep ? '' : 'none';
      if (keep) shown++;
    });
    document.getElementById('case-count').textContent = shown + ' of ' + rows.length + ' cases';
  }
  box.value = decodeURIComponent(location.hash.slice(1));
  box.addEventListener('input', apply);
  apply();
})();
</script>"""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("--history", nargs="+", default=[])
    parser.add_argument("--out")
    args = parser.parse_args()
    doc = load_results(args.run, "report")
    cases = doc["omnishadow"]["cases"]
    timed = [c for c in cases if c.get("timing")]
    out = args.out or os.path.join(args.run, "report.html")
    body = [f"<h1>omnishadow run {esc(doc['omnishadow'].get('commit', ''))}</h1>", incomplete_banner(doc),
            header(doc), "<h2>The answer</h2>", answer_section(timed),
            f"<h2>Status</h2><p>{status_counts(cases)}</p>",
            "<h2>Shadow pass per technique (ratio to six_pass)</h2>",
            ratio_chart(timed, "technique", "six_pass", "shadow", "shadow pass, median wall time / six_pass"),
            "<h2>Lighting pass per filter (ratio to hard)</h2>",
            ratio_chart(timed, "filter", "hard", "lighting", "lighting pass, median wall time / hard"),
            "<h2>Speed against accuracy</h2>", tradeoff_svg(timed),
            "<h2>Many lights</h2>", lights_section(timed),
            "<h2>Failed checks</h2>", failed_checks(doc, args.run)]
    if args.history:
        body += ["<h2>History</h2>", history_section(args.history)]
    body += ["<h2>Every case</h2>", case_table(cases)]
    page = (f"<!doctype html><html><head><meta charset='utf-8'><title>omnishadow report</title>"
            f"<style>{STYLE}</style></head><body>{''.join(body)}</body></html>")
    write_text_atomic(out, page, "report")
    print(f"report: {out}")


if __name__ == "__main__":
    main()
