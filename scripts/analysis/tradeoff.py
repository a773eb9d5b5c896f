#!/usr/bin/python3
"""Speed against accuracy for one or more omnishadow runs.

For every ok case: frame time (median wall of shadow + lighting passes) next to its shadow error against the
ray-cast reference. Marks, per scene and backend, the Pareto-optimal configurations (no other one is both
faster and more accurate), writes tradeoff.md and one tradeoff_<backend>_<scene>.png per group, and compares
the tutorial's two PCF kernels (pcf_disk20 against pcf_grid64): cost ratio, error ratio and how alike they look.

Usage: scripts/analysis/tradeoff.py RUN_DIR [RUN_DIR ...] [--metric mae_sphere|mae_point|misclassified_percent]
                           [--out DIR]
"""
import argparse
import json
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
from results_io import load_results  # noqa: E402


def load_cases(run_dir):
    doc = load_results(run_dir, "tradeoff")
    for case in doc["omnishadow"]["cases"]:
        case["_run"] = run_dir
        yield case


def frame_ms(case):
    t = case.get("timing", {})
    shadow = t.get("shadow", {}).get("cpu_wall_ms") or {}
    lighting = t.get("lighting", {}).get("cpu_wall_ms") or {}
    if "median" not in shadow or "median" not in lighting:
        return None
    return shadow["median"] + lighting["median"]


def pareto(points):
    """Indices of points (time, error) that no other point dominates (<= in both, < in one)."""
    best = []
    for i, (t, e) in enumerate(points):
        dominated = any((t2 <= t and e2 <= e and (t2 < t or e2 < e)) for j, (t2, e2) in enumerate(points) if j != i)
        if not dominated:
            best.append(i)
    return best


def read_pfm(path):
    import numpy as np
    with open(path, "rb") as f:
        data = f.read()
    header, dims, scale, body = data.split(b"\n", 3)
    w, h = map(int, dims.split())
    channels = 3 if header == b"PF" else 1
    return np.frombuffer(body, dtype="<f4", count=w * h * channels).reshape(h, w, channels)


def label(case):
    a = case["axes"]
    return f"{a['technique']} {a['filter']} c{a['cube_size']} {a['storage']} {a['depth_format']}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", help="run folders holding results.json")
    parser.add_argument("--metric", default="mae_sphere",
                        choices=["mae_sphere", "mae_point", "misclassified_percent"],
                        help="error axis (mae_sphere falls back to mae_point where a run has no soft reference)")
    parser.add_argument("--out", help="folder for tradeoff.md and plots (default: the first run folder)")
    args = parser.parse_args()
    out_dir = args.out or args.runs[0]
    os.makedirs(out_dir, exist_ok=True)

    groups = {}
    for run in args.runs:
        for case in load_cases(run):
            acc, ms = case.get("accuracy"), frame_ms(case)
            if case["status"] not in ("ok", "failed_check", "failed_quality") or not acc or ms is None:
                continue
            error = acc.get(args.metric, acc.get("mae_point"))
            key = (case["axes"]["backend"], case["axes"]["scene"])
            groups.setdefault(key, []).append((case, ms, error))
    if not groups:
        sys.exit("tradeoff: no timed case with accuracy figures in " + ", ".join(args.runs))

    md = [f"# Speed against accuracy\n\nError metric: `{args.metric}` against the ray-cast reference "
          "(mae_sphere: the spherical light of the run's `light_radius`). Time: median frame wall time "
          "(shadow + lighting pass). ★ = Pareto-optimal in its scene (nothing else is both faster and more "
          "accurate). Fits light radius: the spherical light (radius in world units, 0 = the point light) whose soft "
          "shadow the case matches best, and the mean abs error there (`accuracy.radius_fit`): which light a filter "
          "imitates, whatever radius the run's reference used. Runs: " + ", ".join(args.runs) + "\n"]
    for (backend, scene), rows in sorted(groups.items()):
        rows.sort(key=lambda r: r[1])
        front = set(pareto([(ms, err) for _, ms, err in rows]))
        md.append(f"\n## {backend} / {scene}\n\n| configuration | frame ms | {args.metric} | misclassified % "
                  "| false / missed shadow % | PSNR point dB | fits light radius (mae) | status |\n"
                  "|---|---|---|---|---|---|---|---|")
        for i, (case, ms, err) in enumerate(rows):
            a = case["accuracy"]
            psnr = a.get("psnr_point_db")
            fit = a.get("radius_fit")
            fits = f"{fit['best_radius']:g} ({fit['best_mae']:.4f})" if fit else "-"
            md.append(f"| {'★ ' if i in front else ''}{label(case)} | {ms:.2f} | {err:.5f} | "
                      f"{a['misclassified_percent']:.3f} | {a['false_shadow_percent']:.3f} / "
                      f"{a['missed_shadow_percent']:.3f} | {'∞' if psnr is None else f'{psnr:.1f}'} | {fits} | "
                      f"{case['status']} |")
        plot(out_dir, backend, scene, rows, front, args.metric)
        md.append(f"\n![{backend} {scene}](tradeoff_{backend}_{scene}.png)\n")
        md.extend(kernel_comparison(rows))

    path = os.path.join(out_dir, "tradeoff.md")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(path + ".tmp", path)
    print(path)


def kernel_comparison(rows):
    """Seed 000/001's claim: the 20-direction disk looks like the 64-sample grid with under a third of the
    samples. Per matching pair: lighting-time ratio, error ratio, and the mean |disk - grid| shadow factor."""
    by_key = {}
    for case, ms, err in rows:
        a = case["axes"]
        key = (a["technique"], a["cube_size"], a["storage"], a["depth_format"])
        by_key.setdefault(key, {})[a["filter"]] = (case, err)
    lines = []
    for key, filters in sorted(by_key.items()):
        if "pcf_disk20" not in filters or "pcf_grid64" not in filters:
            continue
        (disk, disk_err), (grid, grid_err) = filters["pcf_disk20"], filters["pcf_grid64"]
        t_disk = disk["timing"]["lighting"]["cpu_wall_ms"]["median"]
        t_grid = grid["timing"]["lighting"]["cpu_wall_ms"]["median"]
        alike = "n/a"
        try:
            d = read_pfm(os.path.join(disk["_run"], disk["images"]["shadow_factor"]))
            g = read_pfm(os.path.join(grid["_run"], grid["images"]["shadow_factor"]))
            alike = f"{float(abs(d - g).mean()):.4f}"
        except (KeyError, OSError, ImportError, ValueError):
            pass
        ratio = f"{disk_err / grid_err:.3f}" if grid_err > 0 else "n/a"
        lines.append(f"| {key[0]} c{key[1]} {key[2]} | {t_disk:.2f} / {t_grid:.2f} = {t_disk / t_grid:.2f} | "
                     f"{disk_err:.5f} / {grid_err:.5f} = {ratio} | {alike} |")
    if not lines:
        return []
    return ["\n### pcf_disk20 against pcf_grid64 (20 vs 64 samples)\n",
            "| case | lighting ms disk / grid | error disk / grid | mean abs(disk - grid) |", "|---|---|---|---|"] + lines


def plot(out_dir, backend, scene, rows, front, metric):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("tradeoff: matplotlib missing (Debian: python3-matplotlib); no plot", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(9, 6))
    markers = {"hard": "o", "pcf_grid64": "s", "pcf_disk20": "^", "hw_compare2x2": "D", "pcss": "v"}
    for filt, marker in markers.items():
        pts = [(ms, err, case) for case, ms, err in rows if case["axes"]["filter"] == filt]
        if pts:
            ax.scatter([p[0] for p in pts], [max(p[1], 1e-6) for p in pts], marker=marker, label=filt, alpha=0.6)
    frontier = sorted((rows[i][1], max(rows[i][2], 1e-6), rows[i][0]) for i in front)
    ax.plot([p[0] for p in frontier], [p[1] for p in frontier], "k--", linewidth=1, label="Pareto front")
    for ms, err, case in frontier:
        ax.annotate(f"{case['axes']['filter']} c{case['axes']['cube_size']}", (ms, err), fontsize=7,
                    xytext=(4, 4), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("frame time, median wall (ms)")
    ax.set_ylabel(f"{metric} against the ray-cast reference")
    ax.set_title(f"{backend} / {scene}: speed against accuracy")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, f"tradeoff_{backend}_{scene}.png")
    fig.savefig(path + ".tmp.png", dpi=90)
    os.replace(path + ".tmp.png", path)
    plt.close(fig)


if __name__ == "__main__":
    main()
