#!/usr/bin/python3
"""The numerical-stability table from a scripts/experiments/run_extremes.sh run: extremes (rows, with their purpose) against
variants (storage x depth format x filter), each cell the percentage of pixels whose hard/soft shadow disagrees
with exact visibility (ray-cast reference), marked where a case produced NaN/Inf or flickered; then cube sizes
with their status or the limit that applied. Regenerate docs/extremes.md with:
scripts/experiments/run_extremes.sh /tmp/extremes --remedy none,rebase && cp /tmp/extremes/extremes.md docs/extremes.md

Usage: scripts/analysis/extremes_table.py MATRIX_RUN [CUBE_SIZES_RUN] [--out FILE]
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "lib"))
from results_io import load_results  # noqa: E402


def load(run):
    return load_results(run, "extremes_table")


def cell(c):
    if c["status"] == "unsupported":
        return "n/a"
    if c["status"] in ("failed", "resource_error"):
        return c["status"].replace("_", " ")
    nf = c.get("non_finite", {})
    bad = sum(nf.values()) if nf else 0
    acc = c.get("accuracy", {})
    text = f"{acc['misclassified_percent']:.2f}" if "misclassified_percent" in acc else "-"
    if c["status"] in ("failed_check", "failed_quality"):
        text = f"**{text}**"  # beyond --max-error (or another check failed): the variant breaks here
        failed = c.get("reason", "").split(":")[0]
        if c["status"] == "failed_check" and failed and " " not in failed and failed != "moments":
            text += f" ({failed})"  # e.g. cross_backend_shadow_factor
    flick = c.get("stability", {}).get("flicker_percent")
    if flick is not None and flick > 0.5:
        text += f" ~{flick:.1f}"
    if bad:
        text += f" **NaN/Inf {bad}**"
    moments = c.get("moments", {})
    if moments.get("non_finite"):
        text += f" **moments NaN/Inf {moments['non_finite']}**"
    if moments.get("outside"):
        text += f" **moments outside {moments['outside']}**"
    return text


def pivot(doc, row_of, column_of, fmt=cell):
    """A table of fmt(case) with rows row_of(axes) and columns column_of(axes), both in first-seen order."""
    rows, columns, cells = [], [], {}
    for c in doc["omnishadow"]["cases"]:
        a = c["axes"]
        row, col = row_of(a), column_of(a)
        rows += [] if row in rows else [row]
        columns += [] if col in columns else [col]
        cells[(row, col)] = fmt(c)
    return (["| " + " | ".join(["backend / case"] + columns) + " |", "|---|" + "---|" * len(columns)] +
            [f"| {row} | " + " | ".join(cells.get((row, col), "") for col in columns) + " |" for row in rows])


def bleeding_cell(c):
    """missed-shadow % (bleeding) / false-shadow % (darkening) and the mean |shadow - exact|, in %."""
    acc = c.get("accuracy")
    if c["status"] == "unsupported" or not acc:
        return cell(c)
    text = f"{acc['missed_shadow_percent']:.2f} / {acc['false_shadow_percent']:.2f} ({100 * acc['mae_point']:.2f})"
    return f"**{text}**" if c["status"] in ("failed_check", "failed_quality") else text


def remedy_suffix(a):
    return "" if a.get("remedies", "none") == "none" else f" + {a['remedies']}"


MOMENTS_SECTIONS = [
    ("moments_bleeding", "Light bleeding and its reduction (`bleeding`, D32F)",
     "Cells: missed-shadow % (light bleeding: lit where the light is hidden) / false-shadow % (darkening), and in "
     "brackets the mean |shadow - exact| in %. lbr<a>: lit fractions below a taken as shadow, the rest rescaled "
     "(the Chebyshev and Hamburger bounds only; n/a for the others).",
     lambda a: f"{a['backend']} / {a['filter']}", lambda a: a.get("moments_tuning", "none"), bleeding_cell),
    ("moments_exponents", "Exponents about the overflow limit (`nf_25`, far fitted so that z reaches 1)",
     "Columns: the exponent as a fraction of the format's limit ln(max) (half of it for evsm); none = the default "
     "0.9. Above 1 the moments of z near 1 are infinite (D32F) or saturate (a 16-bit conversion may clamp); the "
     "moments check (`--check`) fails both.",
     lambda a: f"{a['backend']} / {a['filter']} {a['depth_format']}", lambda a: a.get("moments_tuning", "none"), cell),
    ("moments_floor", "Singular moments and variance cancellation: variance floor and moment bias off and on",
     "`flat_moments`: the light at a sphere's centre, every texel nearly one distance; `nf_25`: the room. floor<s>: "
     "vsm's variance floor (4 units of the format's rounding of m2) and msm's moment bias times s (floor0: none; "
     "none: the defaults); + bias0: the lookup's bias off too, so that nothing else keeps a surface from shadowing "
     "itself where m2 - m1^2 cancels.",
     lambda a: f"{a['backend']} / `{a['scene']}` {a['filter']} {a['depth_format']}" + remedy_suffix(a),
     lambda a: a.get("moments_tuning", "none"), cell),
    ("moments_world", "VSM with distances in world units",
     "world: (d, d^2) of the distance in world units instead of d / far (near/far 1:25 and 1:1000). The floor is "
     "relative to m2, so the units change only the format's range (d^2 overflows a 16-bit float beyond 256 units, "
     "which these rooms do not reach).",
     lambda a: f"{a['backend']} / `{a['scene']}` {a['depth_format']}" + remedy_suffix(a),
     lambda a: a.get("moments_tuning", "none"), cell),
    ("moments_seams", "Filtering across face seams",
     "`seams` puts casters on the light's diagonals (face seams and corners) in `nf_25`'s room: the moments blur "
     "folds its taps across each seam (shaders/cube_texel.glsl), so the filters should lose no more there than "
     "in the plain room.",
     lambda a: f"{a['backend']} / {a['filter']}", lambda a: f"`{a['scene']}`", cell),
]


LAYOUT_SECTIONS = [
    ("layouts_seams", "Layouts where faces meet (`--layout cube,face_array,tetrahedral`, D32F)",
     "`face_array` stores the cube's texels as six layers of a 2D array and picks the layer in the shader, so its "
     "filtering clamps at each face's edge where the cube's crosses the seam; `tetrahedral`'s four faces meet along "
     "other great circles, with wider texels toward their corners (vsm is not built for it). `seams` puts casters on the light's "
     "diagonals (the cube's seams and corners), `tetra_seams` on the tetrahedral faces' corners and edges and in the "
     "planes where two of them tie (where each face's frustum reaches furthest past its cell: the layout's guard "
     "band), `grazing` lights surfaces at grazing angles, `nf_25` is the plain room. The NEAREST filters (hard, "
     "pcf_disk20) must read the same texels in cube and face_array (the lookup check holds each to the cube-map rule); "
     "hw_compare2x2 (2x2 bilinear compare) and vsm (bilinear moments) may differ at seams. Tetrahedral's texels are "
     "held to their own exact truth (the texel check) and its lookups to its own rule.",
     lambda a: f"{a['backend']} / {a['filter']}", lambda a: f"`{a['scene']}` {a.get('layout', 'cube')}", cell),
    ("layouts_paraboloid", "dual_paraboloid at the equator and at coarse tessellation (D32F)",
     "`dual_paraboloid` warps each vertex into its hemisphere's paraboloid and rasterises straight edges where the "
     "exact map draws curves, so its error depends on the casters' tessellation (`--tessellate n`: every triangle "
     "split into n^2); its two layers meet at the equator (the light's z), which `seams`' diagonal casters cross and "
     "`grazing`'s floor crosses at grazing angles. The cube beside it at the same memory.",
     lambda a: f"{a['backend']} / {a['filter']}",
     lambda a: f"`{a['scene']}` {a.get('layout', 'cube')} t{a.get('tessellation', 1)}", cell),
]


def sections(root, table, heading):
    """One pivot per (folder, title, text, row_of, column_of, fmt) of `table` whose run exists under root."""
    lines = []
    for folder, title, text, row_of, column_of, fmt in table:
        path = os.path.join(root, folder)
        if not os.path.isdir(path):
            continue
        doc = load(path)
        lines += ["", f"{heading} {title}", "", text, "", f"Run: `{command(doc)}`", ""]
        lines += pivot(doc, row_of, column_of, fmt)
    return lines


def moments_sections(root):
    return ["", "## Moments filters' hazards (`--moments-tuning`, cube 512, `--check`)"] + \
        sections(root, MOMENTS_SECTIONS, "###")


def layout_sections(root):
    return sections(root, LAYOUT_SECTIONS, "##")


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES_DIR = os.path.join(ROOT, "scenes", "extremes")


def command(doc):
    """The run's command line with this checkout's path shortened to '.', so the table does not name a machine."""
    return doc["omnishadow"].get("command_line", "?").replace(ROOT + "/", "./")


def purpose(scene):
    try:
        with open(os.path.join(SCENES_DIR, scene + ".json")) as f:
            return json.load(f).get("description", "")
    except (OSError, ValueError):
        return ""


def table(doc, column_of, with_purpose, remedy_in_row=True):
    """Rows (backend, scene[, remedies]) against the columns column_of(axes) names, in first-seen order."""
    rows, columns, cells = {}, [], {}
    for c in doc["omnishadow"]["cases"]:
        a = c["axes"]
        col = column_of(a)
        if col not in columns:
            columns.append(col)
        row = (a["backend"], a["scene"], a.get("remedies", "none") if remedy_in_row else "none")
        rows.setdefault(row, None)
        cells[(row, col)] = cell(c)
    lines = ["| backend / extreme | " + " | ".join(columns) + (" | purpose |" if with_purpose else " |"),
             "|---|" + "---|" * len(columns) + ("---|" if with_purpose else "")]
    for row in sorted(rows):
        remedy = "" if row[2] == "none" else f" + {row[2]}"
        lines.append(f"| {row[0]} / `{row[1]}`{remedy} | " + " | ".join(cells.get((row, c), "") for c in columns) +
                     (f" | {purpose(row[1])} |" if with_purpose else " |"))
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("matrix")
    parser.add_argument("cube_sizes", nargs="?")
    parser.add_argument("--remedies", help="a run with --remedy variants (scripts/experiments/run_extremes.sh makes one)")
    parser.add_argument("--pcf", help="a run with --pcf-scale variants")
    parser.add_argument("--moments", help="the folder holding the moments_* runs of scripts/experiments/run_extremes.sh")
    parser.add_argument("--out")
    args = parser.parse_args()
    doc = load(args.matrix)
    lines = ["# Numerical extremes", "",
             "Generated by `scripts/experiments/run_extremes.sh` + `scripts/analysis/extremes_table.py` (do not edit by hand). Each cell: % of "
             "pixels whose shadow disagrees with exact visibility (ray-cast reference, hard threshold 0.5); "
             "`~x` = x% of pixels changed their shadow on the next frame (flicker, shown above 0.5%); **NaN/Inf** = "
             "non-finite values read back; **bold** = failed_check (beyond `--max-error 1`%). lin = linear distance / far in a depth cube; r32f = distance in an R32F "
             "cube (+ depth buffer of the given format); hw = the rasteriser's projective depth, converted back "
             "in the lookup.", "",
             f"Run: `{command(doc)}`", ""]
    short = {"linear_depth": "lin", "r32f_distance": "r32f", "hardware_depth": "hw"}
    lines += table(doc, lambda a: f"{short.get(a['storage'], a['storage'])} {a['depth_format']} "
                                  f"{a['filter'].replace('pcf_', '')}", True)
    if args.remedies:
        rem = load(args.remedies)
        lines += ["", "## Remedies on and off (linear depth, D32F)", "",
                  "rebase: scene loaded relative to its light in double precision; bias0: no bias; slope_bias: the directional "
                  "notes' max(0.05 (1 - n.l), 0.005); normal_offset: lookup 1.5 texels along the normal; two_sided: "
                  "casters without back-face culling in the shadow pass.", "",
                  f"Run: `{command(rem)}`", ""]
        lines += table(rem, lambda a: f"{a.get('remedies', 'none')} {a['filter'].replace('pcf_', '')}", False,
                       remedy_in_row=False)
    if args.pcf:
        pcf = load(args.pcf)
        lines += ["", "## PCF radius (linear depth, D32F)", "",
                  "Columns: filter and --pcf-scale (0 = every sample in one direction, 1 = the tutorials' kernels).", "",
                  f"Run: `{command(pcf)}`", ""]
        lines += table(pcf, lambda a: f"{a['filter'].replace('pcf_', '')} x{a.get('pcf_scale', 1):g}", False)
    if args.moments:
        lines += moments_sections(args.moments)
        lines += layout_sections(args.moments)
    if args.cube_sizes:
        sizes = load(args.cube_sizes)
        lines += ["", "## Cube sizes (nf_25)", "", "| case | status | misclassified % | reason / limit |",
                  "|---|---|---|---|"]
        for c in sizes["omnishadow"]["cases"]:
            acc = c.get("accuracy", {}).get("misclassified_percent")
            lines.append(f"| `{c['id']}` | {c['status']} | {'-' if acc is None else f'{acc:.2f}'} | "
                         f"{c.get('reason', '')} |")
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out + ".tmp", "w") as f:
            f.write(text)
        os.replace(args.out + ".tmp", args.out)
    print(text)


if __name__ == "__main__":
    main()
