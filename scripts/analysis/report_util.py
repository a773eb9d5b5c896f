#!/usr/bin/python3
"""What report.py and its sections (report_answer.py, report_svg.py) read alike: HTML escaping, and a pass's
median wall time from a case of results.json."""
import html


def esc(x):
    return html.escape(str(x))


def pass_ms(case, p):
    s = case.get("timing", {}).get(p, {}).get("cpu_wall_ms", {})
    return s.get("median")
