#!/usr/bin/python3
"""The house's two structural rules, read from the sources as they stand:

1. No function body runs past 80 lines (C++ as clang-format writes it: a definition starts at column 0 and its
   closing brace is the next line that is only "}").
2. Every #include of a project header points to its own floor or below. The floors, bottom to top:
   scenes < backends < bench/io < bench/truth < bench/run < bench/report < bench/cli, and CMakeLists.txt gives
   each bench floor its own library that links only the floor below (so the linker holds the order too).

A self-test plants a long function and a climbing include first and must catch both.

Usage: house_rules_test.py SOURCE_DIR
"""
import pathlib
import re
import subprocess
import sys

MAX_FUNCTION_LINES = 80
# Bottom to top. A file's floor is the first prefix its path starts with; tests/, fuzz/, samples/ and tools stand
# outside the house and may include anything.
FLOORS = ["scenes/", "backends/", "bench/io/", "bench/truth/", "bench/run/", "bench/report/", "bench/cli/"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def floor_of(path):
    for rank, prefix in enumerate(FLOORS):
        if path.startswith(prefix):
            return rank
    return None


def long_functions(path, text):
    lines = text.split("\n")
    found = []
    for end, line in enumerate(lines):
        if line.rstrip() != "}":
            continue
        start = end - 1
        while start >= 0 and (not lines[start] or lines[start][0].isspace() or lines[start].startswith(("//", "#"))):
            start -= 1
        if start < 0 or lines[start].startswith(("namespace", "struct", "class", "enum", "extern", "union")):
            continue
        if end - start + 1 > MAX_FUNCTION_LINES:
            found.append(f"{path}:{start + 1}: {end - start + 1} lines (at most {MAX_FUNCTION_LINES}): "
                         f"{lines[start].strip()[:70]}")
    return found


def climbing_includes(path, text):
    mine = floor_of(path)
    if mine is None:
        return []
    found = []
    for target in INCLUDE.findall(text):
        theirs = floor_of(target)
        if theirs is not None and theirs > mine:
            found.append(f"{path} includes {target}: {FLOORS[theirs]} stands above {FLOORS[mine]} "
                         f"(floors, bottom to top: {' < '.join(f.rstrip('/') for f in FLOORS)})")
    return found


def self_test():
    long_body = "int f() {\n" + "  x();\n" * 90 + "}\n"
    assert long_functions("a.cpp", long_body), "a 92-line function was not caught"
    assert not long_functions("a.cpp", "int f() {\n  x();\n}\n"), "a short function was caught"
    assert climbing_includes("bench/truth/x.cpp", '#include "bench/run/case_runner.h"\n'), "truth -> run not caught"
    assert climbing_includes("backends/gl/x.cpp", '#include "bench/io/image_io.h"\n'), "backends -> bench not caught"
    assert not climbing_includes("bench/run/x.cpp", '#include "bench/truth/accuracy.h"\n'), "run -> truth caught"


def main():
    root = pathlib.Path(sys.argv[1])
    self_test()
    files = subprocess.run(["git", "-C", str(root), "ls-files", "*.cpp", "*.h"], capture_output=True, text=True,
                           check=True).stdout.split()
    problems = []
    for name in files:
        text = (root / name).read_text(encoding="utf-8", errors="replace")
        problems += long_functions(name, text) + climbing_includes(name, text)
    for p in problems:
        print(p)
    print(f"house rules: {len(files)} files, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
