#!/usr/bin/python3
"""What each frame needs with many lights: one row per policy (where the maps live and at what size, what is culled,
how the lights are shaded, how many faces a frame refreshes), with what the frame rendered and what it cost.

For each backend, scene, light count, cube size and filter: per policy, the faces, texels and shadow passes the
counted frame rendered (results.json shadow_plan.rendered; the frame after the check frame where an update budget
or caching makes a frame depend on the one before), the shadow, lighting and frame median wall times, the texels
as a share of "every light, every face, full size" (optimisations none, no update budget, the uniform cube
array), the misclassified pixels at the check frame and, with a staleness sequence (--staleness-frames), its mean
and worst frame; the Pareto set marked: the policies no other policy of the group beats on both frame time and
error (the sequence's mean where there is one, else the check frame's). Times are the run's device's; on
llvmpipe/lavapipe they are CPU time, so compare within one run only.

Usage: scripts/analysis/policy_table.py RUN_DIR... [--out FILE] [--judge]

Each group ends with the many-light target's verdict: a policy rendering at most a quarter of the texels of every
light, every face, full size for at most half a point more misclassified pixels; --judge exits 1 unless every group
that has that baseline meets it.

Writes FILE (default: the first RUN_DIR's policies.md) and prints it. docs/many-lights.md gives the commands.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
from results_io import load_results, median_ms, write_text_atomic  # noqa: E402
from tradeoff import pareto  # noqa: E402


def policy_of(a):
    """The policy's name: layout (and how its tiles are sized), optimisations, update budget."""
    layout = a.get("layout", "cube")
    if a.get("atlas_tiles", "uniform") != "uniform":
        layout += " " + a["atlas_tiles"]
    if a.get("shadow_budget_texels"):
        layout += f" {a['shadow_budget_texels'] // 1024}K"
    if a.get("atlas_replan_frames"):
        layout += f" replan {a['atlas_replan_frames']}"
    if a.get("atlas_hysteresis_octaves"):
        layout += f" hysteresis {a['atlas_hysteresis_octaves']:g}"
    opt = a.get("optimizations", "none")
    update = a.get("update_budget_faces", 0)
    return f"{layout} / {opt}" + (f" / update {update}" if update else "")


def is_baseline(a):
    """Every light, every face, full size: nothing culled or cached, no budget, every light at --cube."""
    return (a.get("optimizations", "none") == "none" and not a.get("update_budget_faces")
            and a.get("layout") != "atlas")


def frame_ms(case):
    return ((case.get("timing", {}).get("frame_wall_ms") or {}).get("median"))


def figures(case):
    """A case's row figures (None where the run has none)."""
    rendered = case.get("shadow_plan", {}).get("rendered") or {}
    staleness = case.get("staleness") or {}
    wrong = staleness.get("misclassified_percent") or {}
    return {"faces": rendered.get("faces"), "texels": rendered.get("texels"), "passes": rendered.get("passes"),
            "shadow": median_ms(case, "shadow"), "lighting": median_ms(case, "lighting"), "frame": frame_ms(case),
            "check": (case.get("accuracy") or {}).get("misclassified_percent"),
            "mean": wrong.get("mean"), "worst": wrong.get("worst"), "worst_frame": wrong.get("worst_frame"),
            "wait": staleness.get("max_wait_frames"), "status": case["status"]}


def groups_of(cases):
    """{(backend, scene, lights, cube, filter): {policy: case}} of the timed cases."""
    groups = {}
    for c in cases:
        a = c.get("axes", {})
        if frame_ms(c) is None:
            continue
        key = (a["backend"], a["scene"], a.get("light_count", 1), a["cube_size"], a["filter"])
        groups.setdefault(key, {})[policy_of(a)] = c
    return groups


def pareto_set(group):
    """The policies of a group no other beats on both frame time and error: the sequence's mean error where every
    policy of the group ran one (the same lights and frames), else the check frame's."""
    named = [(p, figures(c)) for p, c in group.items()]
    error = "mean" if all(f["mean"] is not None for _, f in named) else "check"
    points = [(p, f["frame"], f[error]) for p, f in named if f["frame"] is not None and f[error] is not None]
    return {points[i][0] for i in pareto([(t, e) for _, t, e in points])}


TEXEL_SHARE, ERROR_POINTS = 0.25, 0.5  # the many-light target: a quarter of the texels, half a point more error


def target(group):
    """The many-light target in one group: a policy that renders at most a quarter of the texels of every light,
    every face, full size for at most half a point more misclassified pixels (the sequence's mean where every policy
    ran one, else the check frame's). (verdict, line): verdict None where the group has no baseline to judge by."""
    named = {p: figures(c) for p, c in group.items()}
    base = next((named[p] for p, c in group.items() if is_baseline(c["axes"])), None)
    if base is None or not base["texels"]:
        return None, "no baseline (optimisations none, no update budget, uniform maps) with its texels"
    error = "mean" if all(f["mean"] is not None for f in named.values()) else "check"
    if base[error] is None:
        return None, "the baseline has no error figure"
    meets = [(f["frame"] or float("inf"), p) for p, f in named.items()
             if f["texels"] is not None and f[error] is not None and f["texels"] <= TEXEL_SHARE * base["texels"]
             and f[error] <= base[error] + ERROR_POINTS]
    if not meets:
        return False, (f"no policy renders <= {TEXEL_SHARE:.0%} of the baseline's {base['texels']} texels within "
                       f"{ERROR_POINTS} points of its {base[error]:.2f}% ({error})")
    _, best = min(meets)
    f = named[best]
    return True, (f"`{best}` renders {f['texels'] / base['texels']:.2f}x the baseline's texels at "
                  f"{f[error]:.2f}% against {base[error]:.2f}% misclassified ({error}), the fastest of "
                  f"{len(meets)} that meet it")


def num(v, fmt):
    return "-" if v is None else format(v, fmt)


def rows_for(group):
    base = next((figures(c)["texels"] for c in group.values() if is_baseline(c["axes"])), None)
    front = pareto_set(group)
    lines = []
    for policy, c in sorted(group.items()):
        f = figures(c)
        share = f"{f['texels'] / base:.2f}" if base and f["texels"] is not None else "-"
        worst = "-" if f["worst"] is None else f"{f['worst']:.2f} (frame {f['worst_frame']})"
        lines.append(f"| `{policy}` | {num(f['faces'], 'd')} | {num(f['texels'], 'd')} | {share} | "
                     f"{num(f['passes'], 'd')} | {num(f['shadow'], '.2f')} | {num(f['lighting'], '.2f')} | "
                     f"{num(f['frame'], '.2f')} | {num(f['check'], '.2f')} | {num(f['mean'], '.2f')} | {worst} | "
                     f"{num(f['wait'], 'd')} | {'yes' if policy in front else ''} | {f['status']} |")
    return lines


HEADER = ("| policy (layout / optimisations / update budget) | faces | texels | texels vs all | passes | shadow ms | "
          "lighting ms | frame ms | misclassified % (check frame) | mean % (sequence) | worst % | longest wait | "
          "Pareto | status |")


def render(docs):
    cases = [c for d in docs for c in d["omnishadow"]["cases"]]
    groups = groups_of(cases)
    if not groups:
        return None
    commands = ", ".join(f"`{d['omnishadow'].get('command_line', '')}`" for d in docs)
    md = ["# What each frame needs: policies against every light, every face, full size\n",
          "Generated by `scripts/analysis/policy_table.py` from the runs " + commands + ". Per policy: what the "
          "counted frame rendered (faces, texels, their share of every light's every face at --cube, shadow "
          "passes), median wall times in ms, and pixels misclassified against exact visibility at the check frame "
          "and over the staleness sequence (mean, worst frame); Pareto: no other policy has both a shorter frame "
          "and a smaller error.\n"]
    for (backend, scene, lights, cube, filt), group in sorted(groups.items()):
        md.append(f"\n## {backend} / {scene} / {lights} lights / cube {cube} / {filt}\n")
        md.append(HEADER)
        md.append("|" + "---|" * (HEADER.count("|") - 1))
        md.extend(rows_for(group))
        verdict, line = target(group)
        md.append(f"\nTarget (a quarter of the texels, at most half a point more error): "
                  f"{'-' if verdict is None else 'PASS' if verdict else 'FAIL'}: {line}")
    return "\n".join(md) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--out")
    parser.add_argument("--judge", action="store_true",
                        help="exit 1 unless every group with a baseline meets the target (gpu_acceptance.sh)")
    args = parser.parse_args()
    docs = [load_results(r, "policy_table") for r in args.runs]
    text = render(docs)
    if text is None:
        sys.exit(f"policy_table: no timed case in {' '.join(args.runs)}")
    write_text_atomic(args.out or os.path.join(args.runs[0], "policies.md"), text, "policy_table")
    print(text)
    if args.judge:
        verdicts = [target(g)[0] for g in groups_of([c for d in docs for c in d["omnishadow"]["cases"]]).values()]
        sys.exit(0 if verdicts and all(v is not False for v in verdicts) and any(verdicts) else 1)


if __name__ == "__main__":
    main()
