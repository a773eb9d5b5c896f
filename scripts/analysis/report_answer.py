#!/usr/bin/python3
"""The report's first section: the answer a run was made for, per backend, scene, cube and frame size.

- the fastest shadow pass: its technique, its median, its ratio to six_pass and its margin over the next one;
- per filter: the lighting pass against hard, and what the filter's shadow costs in accuracy against what it is
  held to (misclassified pixels and the mean error against the point light's exact visibility; the radius of the
  spherical light whose exact soft shadow it matches best, with that error);
- the Pareto set: the cases no other case of the group beats on both frame time and misclassified pixels.

Used by report.py; the inputs are results.json's cases.
"""
import statistics

from report_util import esc, pass_ms
from tradeoff import frame_ms, pareto


def group_of(case):
    a = case["axes"]
    return f"{a['backend']}/{a['scene']}/c{a['cube_size']}/f{a['width']}x{a['height']}"


def fastest_technique(cases):
    """'geometry_shader: 3.27 ms, 0.97x six_pass, 4% ahead of vs_layer' for the group's shadow passes."""
    per = {}
    for c in cases:
        ms = pass_ms(c, "shadow")
        if ms is not None:
            per.setdefault(c["axes"]["technique"], []).append(ms)
    if not per:
        return "no timed shadow pass"
    ranked = sorted((statistics.median(v), t) for t, v in per.items())
    best_ms, best = ranked[0]
    text = f"<b>{esc(best)}</b>: {best_ms:.3f} ms"
    if "six_pass" in per and best != "six_pass":
        text += f", {best_ms / statistics.median(per['six_pass']):.2f}x six_pass"
    if len(ranked) > 1:
        text += f", {100 * (ranked[1][0] / best_ms - 1):.0f}% ahead of {esc(ranked[1][1])}"
    return text


def filter_rows(cases, front_ids):
    """One row per filter: lighting cost against hard, accuracy, whether a case of it is on the Pareto set."""
    per = {}
    for c in cases:
        per.setdefault(c["axes"]["filter"], []).append(c)
    hard = [pass_ms(c, "lighting") for c in per.get("hard", []) if pass_ms(c, "lighting") is not None]
    hard_ms = statistics.median(hard) if hard else None
    rows = []
    for f, fc in sorted(per.items(), key=lambda kv: (kv[0] != "hard", kv[0])):
        ms = [pass_ms(c, "lighting") for c in fc if pass_ms(c, "lighting") is not None]
        cost = "-"
        if ms:
            cost = f"{statistics.median(ms):.3f} ms" + (f" ({statistics.median(ms) / hard_ms:.2f}x)" if hard_ms else "")
        acc = next((c["accuracy"] for c in fc if c.get("accuracy", {}).get("pixels")), None)
        cells = ["-", "-", "-"]
        if acc:
            fit = acc.get("radius_fit")
            cells = [f"{acc['misclassified_percent']:.3g}%", f"{acc['mae_point']:.4f}",
                     f"{fit['best_radius']:g} ({fit['best_mae']:.4f})" if fit else "-"]
        on_front = any(c["id"] in front_ids for c in fc)
        rows.append(f"<tr><td><code>{esc(f)}</code></td><td>{cost}</td>" + "".join(f"<td>{x}</td>" for x in cells)
                    + f"<td class='{'ok' if on_front else 'small'}'>{'yes' if on_front else 'no'}</td></tr>")
    return ("<table><tr><th>filter</th><th>lighting pass (x hard)</th><th>misclassified</th>"
            "<th>mean error (point light)</th><th>best-fit light radius (its mean error)</th>"
            "<th>on the Pareto set</th></tr>" + "".join(rows) + "</table>")


def answer_section(cases):
    groups = {}
    for c in cases:
        groups.setdefault(group_of(c), []).append(c)
    if not groups:
        return "<p class='small'>no case was timed</p>"
    out = ["<p class='small'>Misclassified: pixels whose shadow factor is on the other side of 0.5 from the point "
           "light's exact visibility (ray cast). Mean error: the mean absolute difference from it. A soft filter "
           "blurs the point light's edge by design, so it misclassifies penumbra pixels: judge it by the radius "
           "of the spherical light whose exact soft shadow it matches best. Pareto set: the cases no other case "
           "of the group beats on both frame time and misclassified pixels.</p>"]
    for key, gc in sorted(groups.items()):
        points = [(frame_ms(c), c["accuracy"]["misclassified_percent"], c) for c in gc
                  if frame_ms(c) is not None and c.get("accuracy", {}).get("pixels")]
        front = [points[i][2] for i in pareto([(t, e) for t, e, _ in points])]
        front_ids = {c["id"] for c in front}
        named = ", ".join(f"<code>{esc(c['axes']['technique'])}/{esc(c['axes']['filter'])}</code>"
                          for c in sorted(front, key=frame_ms))
        out.append(f"<h3><code>{esc(key)}</code></h3><p>Fastest shadow pass: {fastest_technique(gc)}. "
                   f"Pareto set: {named or 'none (no case with both timing and accuracy)'}.</p>"
                   + filter_rows(gc, front_ids))
    return "".join(out)
