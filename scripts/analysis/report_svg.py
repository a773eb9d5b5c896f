#!/usr/bin/python3
"""Speed against accuracy as an inline SVG for the report: every case a point whose tooltip (the browser's own,
on hover) names it with its figures, each backend/scene's Pareto front joined and labelled, the legend beside the
plot. No script and no network: the page stays one offline file.
"""
from report_util import esc
from tradeoff import frame_ms, pareto

COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf"]
W, H, LEFT, RIGHT, TOP, BOTTOM = 720, 360, 56, 210, 14, 40  # plot area: LEFT..W-RIGHT, TOP..H-BOTTOM


def scale(lo, hi, a, b):
    span = (hi - lo) or 1.0
    return lambda v: a + (v - lo) / span * (b - a)


def tradeoff_svg(cases):
    """The chart and the list of each group's front, or a line saying no case has both figures."""
    groups = {}
    for c in cases:
        t, e = frame_ms(c), c.get("accuracy", {}).get("misclassified_percent")
        if t is not None and e is not None:
            groups.setdefault(f"{c['axes']['backend']}/{c['axes']['scene']}", []).append((t, e, c))
    if not groups:
        return "<p class='small'>no case with both timing and accuracy</p>"
    points = [p for g in groups.values() for p in g]
    x_max = max(t for t, _, _ in points) * 1.05
    y_max = max(e for _, e, _ in points) * 1.1 or 1.0
    out = [f"<svg width='{W}' height='{H}' font-size='10' "
           f"font-family='system-ui,sans-serif' role='img' aria-label='speed against accuracy'>",
           f"<line x1='{LEFT}' y1='{H - BOTTOM}' x2='{W - RIGHT}' y2='{H - BOTTOM}' stroke='#999'/>",
           f"<line x1='{LEFT}' y1='{TOP}' x2='{LEFT}' y2='{H - BOTTOM}' stroke='#999'/>",
           f"<text x='{(LEFT + W - RIGHT) / 2}' y='{H - 8}' text-anchor='middle'>frame time, ms (shadow + lighting, "
           "median)</text>",
           f"<text x='12' y='{(TOP + H - BOTTOM) / 2}' text-anchor='middle' "
           f"transform='rotate(-90 12 {(TOP + H - BOTTOM) / 2})'>misclassified pixels, %</text>"]
    x = scale(0.0, x_max, LEFT, W - RIGHT)
    y = scale(0.0, y_max, H - BOTTOM, TOP)
    for k in range(5):  # ticks at 0, 1/4, ..., of each axis's range
        tx, ty = x_max * k / 4, y_max * k / 4
        out.append(f"<text x='{x(tx):.1f}' y='{H - BOTTOM + 13}' text-anchor='middle' fill='#666'>{tx:.3g}</text>"
                   f"<text x='{LEFT - 4}' y='{y(ty) + 3:.1f}' text-anchor='end' fill='#666'>{ty:.3g}</text>")
    names = []
    for k, (group, pts) in enumerate(sorted(groups.items())):
        colour = COLOURS[k % len(COLOURS)]
        front = sorted(pareto([(t, e) for t, e, _ in pts]), key=lambda i: pts[i][0])
        if len(front) > 1:
            path = " ".join(f"{x(pts[i][0]):.1f},{y(pts[i][1]):.1f}" for i in front)
            out.append(f"<polyline points='{path}' fill='none' stroke='{colour}' stroke-width='1'/>")
        for i, (t, e, c) in enumerate(pts):
            on = i in front
            out.append(f"<circle cx='{x(t):.1f}' cy='{y(e):.1f}' r='{4 if on else 2.5}' fill='{colour}' "
                       f"fill-opacity='{1 if on else 0.45}'><title>{esc(c['id'])}: {t:.3f} ms, {e:.3f}% "
                       f"misclassified{' (Pareto front)' if on else ''}</title></circle>")
            if on:
                a = c["axes"]
                out.append(f"<text x='{x(t) + 5:.1f}' y='{y(e) - 5:.1f}' fill='{colour}' font-size='8'>"
                           f"{esc(a['technique'])}/{esc(a['filter'])}</text>")
        out.append(f"<circle cx='{W - RIGHT + 16}' cy='{TOP + 14 + 16 * k}' r='4' fill='{colour}'/>"
                   f"<text x='{W - RIGHT + 26}' y='{TOP + 18 + 16 * k}'>{esc(group)}</text>")
        names += [f"<li><code>{esc(pts[i][2]['id'])}</code>: {pts[i][0]:.3f} ms, {pts[i][1]:.3f}%</li>" for i in front]
    out.append(f"<text x='{W - RIGHT + 10}' y='{TOP + 2}' font-weight='600'>Pareto front of each backend/scene"
               "</text></svg>")
    return "".join(out) + "<p>Pareto fronts (hover a point for its case):</p><ul>" + "".join(names) + "</ul>"
