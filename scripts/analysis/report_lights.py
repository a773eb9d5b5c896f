#!/usr/bin/python3
"""The report's many-light section: for a run over several light counts, frame time per light and the checked
lights' error against the number of lights, one inline SVG line per backend/scene/cube/filter/layout/technique
(hover a point for its case) and the same figures as a table. Nothing for a run with one light count.
"""
from many_lights_table import figures, groups_of, several_counts
from policy_table import figures as policy_figures, groups_of as policy_groups, pareto_set
from report_util import esc

W, H, LEFT, RIGHT, TOP, BOTTOM = 720, 300, 56, 250, 14, 40
COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf"]


def series_of(cases):
    """{label: [(lights, frame ms per light, case)]} of the timed cases, by light count."""
    series = {}
    for (backend, scene, cube, filt), group in sorted(groups_of(cases).items()):
        for (layout, technique, lights), c in sorted(group.items()):
            frame = figures(c)["frame"]
            if frame is not None:
                series.setdefault(f"{backend}/{scene}/c{cube}/{filt}/{layout}/{technique}", []).append(
                    (lights, frame / lights, c))
    return series


def chart(series):
    counts = sorted({k for pts in series.values() for k, _, _ in pts})
    y_max = max(v for pts in series.values() for _, v, _ in pts) * 1.1 or 1.0
    x = {k: LEFT + (W - RIGHT - LEFT) * (i / max(len(counts) - 1, 1)) for i, k in enumerate(counts)}
    y = lambda v: H - BOTTOM - (H - BOTTOM - TOP) * v / y_max  # noqa: E731
    out = [f"<svg width='{W}' height='{H}' font-size='10' font-family='system-ui,sans-serif' role='img' "
           "aria-label='frame time per light against the number of lights'>",
           f"<line x1='{LEFT}' y1='{H - BOTTOM}' x2='{W - RIGHT}' y2='{H - BOTTOM}' stroke='#999'/>",
           f"<line x1='{LEFT}' y1='{TOP}' x2='{LEFT}' y2='{H - BOTTOM}' stroke='#999'/>",
           f"<text x='{(LEFT + W - RIGHT) / 2}' y='{H - 8}' text-anchor='middle'>point lights</text>",
           f"<text x='12' y='{(TOP + H - BOTTOM) / 2}' text-anchor='middle' "
           f"transform='rotate(-90 12 {(TOP + H - BOTTOM) / 2})'>frame ms per light (median)</text>"]
    for k in counts:
        out.append(f"<text x='{x[k]:.1f}' y='{H - BOTTOM + 13}' text-anchor='middle' fill='#666'>{k}</text>")
    for t in range(5):
        v = y_max * t / 4
        out.append(f"<text x='{LEFT - 4}' y='{y(v) + 3:.1f}' text-anchor='end' fill='#666'>{v:.3g}</text>")
    for n, (label, pts) in enumerate(sorted(series.items())):
        colour = COLOURS[n % len(COLOURS)]
        out.append(f"<polyline points='{' '.join(f'{x[k]:.1f},{y(v):.1f}' for k, v, _ in pts)}' fill='none' "
                   f"stroke='{colour}' stroke-width='1.2'/>")
        for k, v, c in pts:
            wrong = figures(c)["misclassified"]
            out.append(f"<circle cx='{x[k]:.1f}' cy='{y(v):.1f}' r='3' fill='{colour}'><title>{esc(c['id'])}: "
                       f"{v:.3f} ms a light{'' if wrong is None else f', {wrong:.2f}% misclassified'}</title>"
                       "</circle>")
        if n < 16:
            out.append(f"<circle cx='{W - RIGHT + 14}' cy='{TOP + 6 + 12 * n}' r='3' fill='{colour}'/>"
                       f"<text x='{W - RIGHT + 22}' y='{TOP + 9 + 12 * n}' font-size='8'>{esc(label)}</text>")
    return "".join(out) + "</svg>"


def policies_section(cases):
    """Per backend/scene/light count with more than one policy (optimisations, update budget, tiles): what each
    rendered and cost, the Pareto set marked (policy_table.py's figures); "" where no group has two."""
    out = []
    for (backend, scene, lights, cube, filt), group in sorted(policy_groups(cases).items()):
        if len(group) < 2:
            continue
        front = pareto_set(group)
        rows = []
        for policy, c in sorted(group.items()):
            f = policy_figures(c)
            cells = [f["faces"], f["texels"], f["passes"], f["frame"], f["check"], f["mean"], f["worst"]]
            text = "".join("<td>-</td>" if v is None else f"<td>{v:.2f}</td>" if isinstance(v, float)
                           else f"<td>{v}</td>" for v in cells)
            mark = "<b>Pareto</b>" if policy in front else ""
            rows.append(f"<tr><td><code>{esc(policy)}</code></td>{text}<td>{mark}</td></tr>")
        out.append(f"<h3>{esc(backend)} / {esc(scene)} / {lights} lights / cube {cube} / {esc(filt)}</h3>"
                   "<table><tr><th>policy (layout / optimisations / update budget)</th><th>faces</th><th>texels</th>"
                   "<th>passes</th><th>frame ms</th><th>misclassified % (check frame)</th><th>mean % (sequence)</th>"
                   f"<th>worst %</th><th></th></tr>{''.join(rows)}</table>")
    if not out:
        return ""
    return ("<p class='small'>What each frame needs: per policy, what the counted frame rendered and its median "
            "frame time, with the error at the check frame and over the staleness sequence; Pareto: no other "
            "policy has both a shorter frame and a smaller error (scripts/analysis/policy_table.py).</p>" +
            "".join(out))


def lights_section(cases):
    """The section's HTML: the chart and the table, or a line saying the run has one light count; then the
    policies, where a light count has several."""
    if not several_counts(cases):
        return ("<p class='small'>one light count in this run (--light-count 1,4,16,64 measures many)</p>" +
                policies_section(cases))
    series = series_of(cases)
    counts = sorted({k for pts in series.values() for k, _, _ in pts})
    rows = []
    for label, pts in sorted(series.items()):
        by = {k: (v, figures(c)["misclassified"]) for k, v, c in pts}
        cells = "".join(f"<td>{by[k][0]:.2f} ms{'' if by[k][1] is None else f', {by[k][1]:.2f}%'}</td>"
                        if k in by else "<td>-</td>" for k in counts)
        rows.append(f"<tr><td><code>{esc(label)}</code></td>{cells}</tr>")
    head = "".join(f"<th>{k} {'light' if k == 1 else 'lights'}</th>" for k in counts)
    return (chart(series) + "<p class='small'>Each cell: frame time per light (median / K) and the pixels "
            "misclassified against exact visibility, pooled over the lights checked (results.json "
            "accuracy.per_light). docs/many-lights.md reads them.</p>"
            f"<table><tr><th>backend/scene/cube/filter/layout/technique</th>{head}</tr>{''.join(rows)}</table>" +
            policies_section(cases))
