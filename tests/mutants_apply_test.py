#!/usr/bin/python3
"""Every mutant of scripts/experiments/mutant_table.py (the list mutants.py runs) still applies to this tree: each
names text that occurs exactly as often as it expects, and changes the file. A source edit that moves a mutant's text
breaks the mutation study only when someone runs it (6-9 minutes a mutant); this finds it in a second. The list is the
one docs/mutants.md records as caught, name for name: an emptied or shortened list fails here rather than passing as
"0 of 0"."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts", "experiments"))
import mutant_table  # noqa: E402


def documented_mutants():
    with open(os.path.join(ROOT, "docs", "mutants.md")) as f:
        return [m.group(1) for m in re.finditer(r"^\| `([^`]+)` \|", f.read(), re.M)]


def main():
    broken = []
    documented, listed = documented_mutants(), [entry[0] for entry in mutant_table.MUTANTS]
    for name in sorted(set(documented) - set(listed)):
        broken.append(f"{name}: in docs/mutants.md's table, not in mutant_table.py")
    for name in sorted(set(listed) - set(documented)):
        broken.append(f"{name}: in mutant_table.py, not in docs/mutants.md's table (run it: mutants.py --only {name})")
    if not documented:
        broken.append("docs/mutants.md lists no mutant")
    applied = 0
    for entry in mutant_table.MUTANTS:
        name, path, apply = entry[0], entry[1], entry[2]
        with open(os.path.join(ROOT, path)) as f:
            text = f.read()
        try:
            if apply(text) == text:
                broken.append(f"{name}: leaves {path} unchanged")
            else:
                applied += 1
        except ValueError as e:
            broken.append(f"{name}: {path}: {e}")
    for line in broken:
        print("FAIL", line)
    print(f"{applied} of {len(listed)} mutants apply; docs/mutants.md records {len(documented)}")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
