#!/usr/bin/python3
"""Every mutant of scripts/experiments/mutants.py still applies to this tree: each names text that occurs exactly as
often as it expects, and changes the file. A source edit that moves a mutant's text breaks the mutation study only
when someone runs it (6-9 minutes a mutant); this finds it in a second."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "experiments"))
import mutants  # noqa: E402


def main():
    broken = []
    for entry in mutants.MUTANTS:
        name, path, apply = entry[0], entry[1], entry[2]
        with open(os.path.join(ROOT, path)) as f:
            text = f.read()
        try:
            if apply(text) == text:
                broken.append(f"{name}: leaves {path} unchanged")
        except ValueError as e:
            broken.append(f"{name}: {path}: {e}")
    for line in broken:
        print("FAIL", line)
    print(f"{len(mutants.MUTANTS) - len(broken)} of {len(mutants.MUTANTS)} mutants apply")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
