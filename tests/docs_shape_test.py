#!/usr/bin/python3
"""README.md stays a page a newcomer reads (under 200 lines, the two commands its first section), and every relative
link in README.md, docs/, tests/, results/ and scenes/ Markdown files points to a file that exists (anchors are not
checked). A self-test plants a broken link and a long README and shows both are caught.

Usage: docs_shape_test.py SOURCE_DIR
"""
import pathlib
import re
import sys

README_LINES = 200
LINK = re.compile(r"\]\(([^)\s]+)\)")


def readme_problems(text):
    found = []
    lines = text.splitlines()
    if len(lines) >= README_LINES:
        found.append(f"README.md: {len(lines)} lines (under {README_LINES}: move the rest to docs/)")
    sections = [l for l in lines if l.startswith("## ")]
    if not sections or not sections[0].startswith("## The two commands"):
        found.append("README.md: its first section is not the two commands")
    return found


def link_problems(path, text):
    found = []
    for target in LINK.findall(text):
        if target.startswith(("http://", "https://", "mailto:", "#")):
            continue
        file = target.split("#")[0]
        if file and not (path.parent / file).exists():
            found.append(f"{path}: link to {target}: no such file")
    return found


def main():
    root = pathlib.Path(sys.argv[1])
    if not readme_problems("x\n" * 300) or not link_problems(root / "README.md", "[a](no/such/file.md)"):
        print("FAIL: the self-test's planted long README or broken link was not caught")
        return 1
    found = readme_problems((root / "README.md").read_text())
    files = [root / "README.md"] + [p for d in ("docs", "tests", "results", "scenes") for p in (root / d).rglob("*.md")]
    for f in files:
        found += link_problems(f, f.read_text())
    for p in found:
        print(f"FAIL: {p}")
    if not found:
        print(f"README.md in shape; the relative links of {len(files)} Markdown files resolve")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
