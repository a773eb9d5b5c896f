"""Reading an omnishadow run folder's results.json for the scripts (tradeoff, optimizations_table,
extremes_table, filter_table, layout_table): one place that says what a missing or foreign file is, and the
figures the tables share."""
import json
import os
import sys


def load_results(run_dir, tool):
    """The parsed results.json of run_dir; exits with a one-line message naming the file on anything else."""
    path = os.path.join(run_dir, "results.json")
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"{tool}: cannot read {path}: {e}")
    if not isinstance(doc, dict) or "omnishadow" not in doc:
        sys.exit(f"{tool}: {path} is not an omnishadow results file (no 'omnishadow' section)")
    return doc


def median_ms(case, pass_name):
    """The median wall time (ms) of a case's timed frames in one pass (shadow, lighting); None when not timed."""
    m = case.get("timing", {}).get(pass_name, {}).get("cpu_wall_ms") or {}
    return m.get("median")


def ratio(value, base):
    """value / base as '1.23x', '-' where either is missing."""
    return f"{value / base:.2f}x" if value is not None and base else "-"
