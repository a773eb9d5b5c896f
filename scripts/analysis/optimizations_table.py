#!/usr/bin/python3
"""What each work-avoiding switch saves, from one run with several --optimize sets.

For every (backend, scene, cube, technique, filter) group that ran with `none` and other sets: the shadow pass's
work counters at the check frame (draws, primitives submitted, VS and GS invocations, GS primitives, fragment
shader invocations; llvmpipe counts fragments in 4x4 blocks), the plan's empty faces and light far, and the
shadow pass's median wall time over the timed frames, with its ratio to `none`, plus the cold first frame.
Cases whose images differ from the unoptimised six_pass case are flagged (culling and caching must not change a
value). Writes optimizations.md next to the run (or --out) and prints it.

Usage: scripts/analysis/optimizations_table.py RUN_DIR [--out FILE]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
from results_io import load_results  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("--out")
    args = parser.parse_args()
    doc = load_results(args.run, "optimizations_table")

    groups = {}
    for c in doc["omnishadow"]["cases"]:
        if c.get("status") not in ("ok", "failed_check", "failed_quality"):
            continue
        a = c["axes"]
        key = (a["backend"], a["scene"], a["cube_size"], a["technique"], a["filter"], a["storage"], a["depth_format"])
        groups.setdefault(key, {})[a.get("optimizations", "none")] = c

    lines = ["# Work avoided per switch (shadow pass, per frame)", "",
             f"Run: `{doc['omnishadow'].get('command_line', '?')}`", "",
             "| backend/scene/cube/technique/filter | optimise | draws | primitives | VS inv. | GS inv. | GS prims | "
             "FS inv. | empty faces | far | shadow ms (x none) | first frame ms | images |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(groups):
        variants = groups[key]
        if "none" not in variants or len(variants) < 2:
            continue
        base_ms = shadow_ms(variants["none"])
        order = ["none"] + sorted(v for v in variants if v != "none")
        for v in order:
            c = variants[v]
            k = c.get("counters", {}).get("shadow", {})
            plan = c.get("shadow_plan", {})
            ms = shadow_ms(c)
            ratio = f" ({ms / base_ms:.2f})" if ms is not None and base_ms else ""
            first = c.get("first_frame", {}).get("shadow_wall_ms")
            checks_ok = all(ch.get("passed", True) for ch in c.get("checks", []))
            lines.append(
                f"| `{key[0]}/{key[1]}/c{key[2]}/{key[3]}/{key[4]}` | {v} | {k.get('draw_calls', '-')} | "
                f"{k.get('primitives_submitted', '-')} | {k.get('vs_invocations', '-')} | {k.get('gs_invocations', '-')} | "
                f"{k.get('gs_primitives', '-')} | {k.get('fs_invocations', '-')} | {plan.get('empty_faces', '-')} | "
                f"{plan.get('light_far', 0):.2f} | {fmt(ms)}{ratio} | {fmt(first)} | "
                f"{'same' if checks_ok else '**differ**'} |")
    text = "\n".join(lines) + "\n"
    out = args.out or os.path.join(args.run, "optimizations.md")
    with open(out + ".tmp", "w") as f:
        f.write(text)
    os.replace(out + ".tmp", out)
    print(text)


def shadow_ms(case):
    s = case.get("timing", {}).get("shadow", {}).get("cpu_wall_ms") or {}
    return s.get("median")


def fmt(v):
    return "-" if v is None else f"{v:.2f}"


if __name__ == "__main__":
    main()
