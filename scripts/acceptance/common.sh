#!/usr/bin/env bash
# What every step of scripts/gpu_acceptance.sh shares: the summary's lines, exit codes that fail the script,
# a run folder's statuses and phases, and the checks' verdict. Sourced by gpu_acceptance.sh after it set out,
# here, bin and summary.

note() { echo "$*" | tee -a "$summary"; }
failed=0
# Records a command's exit code; any but 0 makes the script exit 1 at the end (after every step ran).
exit_note() { local code=$1; shift; note "- $*: exit $code"; [ "$code" -eq 0 ] || failed=1; }

# Statuses, untimed/timed seconds and the clock range of a run folder, one line each.
describe_run() {
  /usr/bin/python3 - "$1" <<'PY' | tee -a "$summary"
import collections, json, sys
doc = json.load(open(sys.argv[1] + "/results.json"))["omnishadow"]
cases = doc["cases"]
print("- statuses:", dict(collections.Counter(c["status"] for c in cases)))
for c in cases:
    if c["status"] not in ("ok", "unsupported"):
        print(f"  - {c['id']}: {c['status']}: {c.get('reason', '')[:200]}")
p = doc.get("phases", {})
if p:
    u, t = p.get("untimed_seconds", 0), p.get("timed_seconds", 0)
    print(f"- untimed {u:.1f} s, timed {t:.1f} s: untimed is {100 * u / max(u + t, 1e-9):.0f}% of the run")
clocks = [s.get("clock_mhz") for c in cases for s in c.get("device_state", {}).get("samples", []) if s.get("clock_mhz")]
if clocks:
    print(f"- graphics clock over the run: {min(clocks):.0f}-{max(clocks):.0f} MHz ({len(clocks)} samples); "
          f"cases warned: {sum(1 for c in cases if c.get('device_state', {}).get('warning'))}")
PY
}

# PASS when the run's untimed part is at most $2 times its timed part (checks cheaper than the timing).
judge_untimed() {
  /usr/bin/python3 - "$1" "$2" <<'PY' | tee -a "$summary"
import json, sys
p = json.load(open(sys.argv[1] + "/results.json"))["omnishadow"].get("phases", {})
u, t, limit = p.get("untimed_seconds"), p.get("timed_seconds"), float(sys.argv[2])
if u is None or not t:
    print("- FAIL: untimed/timed: the run recorded no phases")
    sys.exit(1)
ok = u <= limit * t
print(f"- {'PASS' if ok else 'FAIL'}: untimed {u:.1f} s is {u / t:.2f}x the timed {t:.1f} s (target <= {limit}x)")
sys.exit(0 if ok else 1)
PY
}

# PASS when no case failed a check, and the only quality failures are the cases named in $2 (a regex over ids):
# heavy at cube 64 misclassifies 13% on every device, a real quality limit, not a false alarm.
judge_checks() {
  /usr/bin/python3 "$here/scripts/analysis/judge_checks.py" "$1" --allow "${2:-^$}" | tee -a "$summary"
  return "${PIPESTATUS[0]}"
}

# A run's checks judged (judge_checks) and its table written by scripts/analysis/TABLE: RUN TABLE OUT.
judge_and_tabulate() {
  judge_checks "$1" || failed=1
  /usr/bin/python3 "$here/scripts/analysis/$2" "$1" --out "$3" >/dev/null 2>&1
  exit_note $? "$2 ($3)"
}
