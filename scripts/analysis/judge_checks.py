#!/usr/bin/python3
"""Did a run's checks raise a false alarm? Judges a run folder whose every case is a correct implementation (a
matrix run with --check on code under no planted bug): a case that failed a check (failed_check) is a false alarm;
one that failed otherwise (failed, failed_quality, resource_error, crashed) is a failure unless its id matches
--allow (a run that expects some quality limits to be missed names them); ok and unsupported pass. A case cut at a
run's time budget (interrupted, with no finding beyond ok, failed_quality or interrupted) is counted apart, not
failed. A flaky case (its process died, a fresh one finished it: `crashed_before`, run --crash-retries) passes on its
own status and is named, so that a driver that crashed once is seen.

Usage: scripts/analysis/judge_checks.py RUN_DIR [--allow REGEX]

Prints one markdown line, PASS or FAIL with the counts, then up to 20 failing cases with their reasons; exits 1 on
FAIL. scripts/gpu_acceptance.sh judges its check runs with it, scripts/ci/large_cube_checks.sh its sweep.
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
from results_io import load_results  # noqa: E402


def cut_clean(case):
    """A case stopped at a budget before its timing, nothing failed (interrupted outranks failed_check in a case's
    status, so its findings say)."""
    return case["status"] == "interrupted" and all(
        f.get("status") in ("ok", "failed_quality", "interrupted") for f in case.get("findings", []))


def failures(cases, allowed):
    """The cases that fail the judgement: every failed_check, and any other failure whose id `allowed` misses."""
    return [c for c in cases if c["status"] == "failed_check" or
            (c["status"] not in ("ok", "unsupported", "failed_check") and not cut_clean(c) and
             not allowed.search(c["id"]))]


def verdict(cases, allowed):
    """(lines, passed): the summary line and the failing cases, as printed."""
    bad = failures(cases, allowed)
    ok = sum(c["status"] == "ok" for c in cases)
    unsupported = sum(c["status"] == "unsupported" for c in cases)
    flaky = [c for c in cases if c.get("crashed_before")]
    lines = [f"- {'PASS' if not bad else 'FAIL'}: {ok} ok, {unsupported} unsupported, {len(bad)} failed beyond the "
             f"expected quality limit, {sum(cut_clean(c) for c in cases)} cut by the budget before their timing, "
             f"of {len(cases)}" + (f"; {len(flaky)} flaky (the process died, a fresh one finished)" if flaky else "")]
    lines += [f"  - {c['id']}: {c['status']}: {c.get('reason', '')[:240]}" for c in bad[:20]]
    for c in flaky[:20]:
        last = c["crashed_before"][-1]
        lines.append(f"  - {c['id']}: flaky: died by {last.get('signal', '?')} in step {last.get('step', '?')} "
                     f"({len(c['crashed_before'])} of {len(c['crashed_before']) + 1} attempts), then {c['status']}")
    return lines, not bad


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir")
    parser.add_argument("--allow", default="^$", help="regex of case ids whose failure (not failed_check) is expected")
    args = parser.parse_args()
    try:
        allowed = re.compile(args.allow)
    except re.error as e:
        sys.exit(f"judge_checks.py: --allow '{args.allow}' is not a regular expression: {e}")
    cases = load_results(args.run_dir, "judge_checks.py")["omnishadow"].get("cases", [])
    if not cases:
        sys.exit(f"judge_checks.py: {os.path.join(args.run_dir, 'results.json')} holds no case: nothing was judged")
    lines, passed = verdict(cases, allowed)
    print("\n".join(lines))
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
