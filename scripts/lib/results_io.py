"""Reading an omnishadow run folder's results.json for the scripts (tradeoff, optimizations_table,
extremes_table): one place that says what a missing or foreign file is."""
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
