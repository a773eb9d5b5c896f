#!/usr/bin/python3
"""Injected-work calibration and the precision verdict (scripts/experiments/calibration.py, sensitivity.py), both
sides, on made-up runs: doubling stops at the first batch that reaches the largest target and interpolates each
target between the counts around it; a device where no count shows is a clean exit naming the frame size; the GPU
metric reads only repetitions whose timer passed its check; the verdict passes a gate that finds the slowed cases at
<= 1% false alarms and fails one that misses them or cries wolf."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "experiments"))
import calibration  # noqa: E402
import sensitivity  # noqa: E402

failures = []


def check(condition, what):
    print(("ok: " if condition else "FAILED: ") + what)
    if not condition:
        failures.append(what)


def fake_run(cost_per_iteration, base=1.0, reliable=True):
    """A runner whose every case costs base + n * cost_per_iteration ms in every metric; records the batches."""
    batches = []

    def run(counts):
        batches.append(list(counts))
        entries = []
        for case in ("a", "b", "c"):
            for n in counts:
                t = base + n * cost_per_iteration
                entries.append({"run_type": "iteration", "omnishadow_case": f"gl/{case}/inj{n}", "real_time": t,
                                "frame_cpu_ms": t, "gpu_timer_reliable": 1.0 if reliable else 0.0,
                                "shadow_gpu_ms": t / 2, "lighting_gpu_ms": t / 2})
        return {"benchmarks": entries}
    return run, batches


def doubling():
    run, batches = fake_run(0.001)  # 1 ms frames, 0.1% per iteration: +2% at 20, +5% at 50
    counts, measured = calibration.calibrate(run, "gpu", [0.02, 0.05])
    check(batches == [[0, 1, 2, 4, 8, 16], [0, 32, 64, 128, 256, 512]],
          f"calibration: doubles in batches of five until a count reaches +5% ({batches})")
    check(counts == {0.02: 20, 0.05: 50}, f"calibration: +2% = 20 and +5% = 50 iterations interpolated ({counts})")
    check(abs(measured[64] - 0.064) < 1e-9, "calibration: measured slowdown per count is the median case's")


def never_shows():
    run, _ = fake_run(0.0)
    try:
        calibration.calibrate(run, "wall", [0.05], limit=1 << 10)
        check(False, "calibration: work that never shows must end the script")
    except SystemExit as e:
        check("CI_MATRIX_SIZE=gpu" in str(e) and "slowed the median case by only" in str(e),
              f"calibration: a clean exit naming the remedy ({e})")


def gpu_needs_a_checked_timer():
    run, _ = fake_run(0.001, reliable=False)
    doc = run([0, 8])
    check(calibration.case_medians(doc, "gpu") == {}, "gpu metric: repetitions with an unchecked timer add nothing")
    check(len(calibration.case_medians(doc, "wall")) == 6, "wall metric: every repetition counts")


def verdicts():
    # Three trials of four cases; the 2% arm slowed cases a, b by 3% and c, d by 1% (below the target: not judged).
    def cases(changes, p):
        return [{"id": k, "change": v, "p_adjusted": p} for k, v in changes.items()]
    slow = {"a": 0.03, "b": 0.03, "c": 0.01, "d": 0.01}
    outcomes = {"slow2": [cases(slow, 0.001)] * 3}
    grid = [{"alpha": 0.05, "min_effect": 0.0, "same": {"case_rate": 0.05}},
            {"alpha": 0.05, "min_effect": 0.02, "same": {"case_rate": 0.0}}]
    passed, why = sensitivity.verdict(outcomes, grid, 2)
    check(passed and "alpha 0.05, minimum effect 2.0%" in why and "of the 2 cases" in why,
          f"verdict: PASS where a quiet gate flags every case slowed >= 2% ({why})")
    missed = {"slow2": [cases(slow, 0.2)] * 3}
    passed, why = sensitivity.verdict(missed, grid, 2)
    check(not passed and "0% of the 2 cases" in why, f"verdict: FAIL where the slowed cases are not flagged ({why})")
    loud = [{"alpha": 0.05, "min_effect": 0.0, "same": {"case_rate": 0.02}}]
    passed, why = sensitivity.verdict(outcomes, loud, 2)
    check(not passed and "no gate keeps false alarms" in why, f"verdict: FAIL where every gate cries wolf ({why})")
    passed, why = sensitivity.verdict({"slow2": [cases({"a": 0.005}, 0.001)]}, grid, 2)
    check(not passed and "calibration missed" in why, f"verdict: FAIL where nothing was slowed enough ({why})")


doubling()
never_shows()
gpu_needs_a_checked_timer()
verdicts()
print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
