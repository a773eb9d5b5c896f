"""Reading an omnishadow run folder's results.json for the scripts (tradeoff, optimizations_table,
extremes_table, filter_table, layout_table, report, history): one place that says what a missing or foreign
file is, the figures the tables share, and how their outputs are written."""
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


def write_text_atomic(path, text, tool, option="--out"):
    """Writes text to path through a temporary file beside it (a reader sees the old file or the new, never half),
    or exits 2 with one line naming the option and the path: a folder, a missing parent, no permission. No
    temporary file is left behind."""
    if os.path.isdir(path):
        print(f"{tool}: {option} {path} is a folder: give a file name",
              file=sys.stderr)
        sys.exit(2)
    tmp = f"{path}.tmp.{os.getpid()}"
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        print(f"{tool}: {option} {path}: cannot write: {e.strerror}", file=sys.stderr)
        sys.exit(2)



def table_main(doc, render, tool, default_file, nothing):
    """The command line of a table script: RUN_DIR [--out FILE]; render(results) gives the markdown or None
    (then exit with `nothing`); written atomically to --out or RUN_DIR/default_file, and printed."""
    import argparse
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run")
    parser.add_argument("--out")
    args = parser.parse_args()
    text = render(load_results(args.run, tool))
    if text is None:
        sys.exit(f"{tool}: {nothing} in {args.run}")
    write_text_atomic(args.out or os.path.join(args.run, default_file), text, tool)
    print(text)
