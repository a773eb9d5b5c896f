#!/usr/bin/python3
"""scripts/analysis/judge_checks.py on made-up runs: a failed check is a false alarm even where --allow names its
case, another failure passes only where --allow names it, a case cut at its budget with nothing failed is counted
apart, a flaky case (crashed, then finished) passes and is named, and a run with no results or no case is a
one-line error, never a PASS."""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
JUDGE = os.path.join(ROOT, "scripts", "analysis", "judge_checks.py")


def case(case_id, status, findings=None):
    c = {"id": case_id, "status": status, "reason": f"{status} reason of {case_id}"}
    if findings is not None:
        c["findings"] = [{"status": s} for s in findings]
    return c


def judge(work, name, cases, *extra):
    """(exit code, stdout, stderr) of the judge on a run folder holding `cases` (None: no results.json)."""
    run = os.path.join(work, name)
    os.makedirs(run)
    if cases is not None:
        with open(os.path.join(run, "results.json"), "w") as f:
            json.dump({"benchmarks": [], "omnishadow": {"cases": cases}}, f)
    done = subprocess.run([sys.executable, JUDGE, run, *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True)
    return done.returncode, done.stdout, done.stderr


def expect(result, code, text, what):
    rc, out, err = result
    assert rc == code, f"{what}: exit {rc}, wanted {code}\n{out}{err}"
    assert text in out + err, f"{what}: '{text}' not in\n{out}{err}"


def main():
    good = [case("gl/room/c1024/six_pass", "ok"), case("vulkan/room/c1024/mesh_shader", "unsupported")]
    with tempfile.TemporaryDirectory() as work:
        expect(judge(work, "good", good), 0, "PASS: 1 ok, 1 unsupported, 0 failed", "every case ok or unsupported")
        alarm = good + [case("gl/heavy/c2048/vs_layer", "failed_check")]
        expect(judge(work, "alarm", alarm), 1, "FAIL: 1 ok, 1 unsupported, 1 failed", "a failed check")
        expect(judge(work, "alarm-allowed", alarm, "--allow", "heavy"), 1, "gl/heavy/c2048/vs_layer: failed_check",
               "a failed check whose id --allow matches")
        quality = good + [case("gl/heavy/c64/six_pass", "failed_quality")]
        expect(judge(work, "quality", quality), 1, "FAIL", "a quality failure nobody expected")
        expect(judge(work, "quality-allowed", quality, "--allow", "/heavy/c64/"), 0, "PASS",
               "a quality failure --allow names")
        crashed = good + [case("vulkan/room/c1024/multiview", "crashed")]
        expect(judge(work, "crashed", crashed, "--allow", "/c64/"), 1, "multiview: crashed", "a crash")
        flaky_case = case("vulkan/room/c1024/mesh_shader", "ok")
        flaky_case["crashed_before"] = [{"signal": "SIGSEGV", "step": "check_frame", "phase": "checks", "attempts": 1}]
        flaky = good + [flaky_case]
        expect(judge(work, "flaky", flaky), 0, "1 flaky", "a case that crashed once and then finished passes")
        expect(judge(work, "flaky-named", flaky), 0, "mesh_shader: flaky: died by SIGSEGV in step check_frame",
               "and is named")
        cut = good + [case("gl/hall/l64/six_pass", "interrupted", ["ok", "failed_quality", "interrupted"])]
        expect(judge(work, "cut", cut), 0, "1 cut by the budget", "a case cut at its budget, nothing failed")
        cut_alarm = good + [case("gl/hall/l64/six_pass", "interrupted", ["failed_check", "interrupted"])]
        expect(judge(work, "cut-alarm", cut_alarm), 1, "FAIL", "a cut case whose findings hold a failed check")
        expect(judge(work, "missing", None), 1, "results.json", "no results.json")
        expect(judge(work, "empty", []), 1, "holds no case", "a run with no case")
        expect(judge(work, "bad-regex", good, "--allow", "("), 1, "--allow '(' is not a regular expression",
               "an --allow that is no regex")
    print("judge_checks.py: failed checks always fail, expected failures pass only where named, empty runs refused")


if __name__ == "__main__":
    main()
