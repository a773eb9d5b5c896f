#!/usr/bin/python3
"""Every option that takes a value has a row in the bad-input table (tests/cli_bad_input_test.cpp's CliBadInput): a bad
value of it is shown to be one line naming the option and exit 2. The CLI's own help is the source of the
options (`omnishadow SUBCOMMAND --help`, as options_documented_test.py reads it): an option whose help shows a
value type (TEXT, INT, FLOAT, UINT, ...) must appear in some row of its subcommand; flags take no value. Each
subcommand also needs a row of its own (its positional paths). A self-test plants an option without a row and
shows it is caught.

Usage: bad_input_coverage_test.py OMNISHADOW CLI_TEST_CPP
"""
import re
import subprocess
import sys

SUBCOMMANDS = ["list", "run", "compare", "merge", "report", "history", "alerts", "accept", "threshold", "store", "fetch",
               "export"]
VALUE_OPTION = re.compile(r"^\s+(?:-\w,)?(--[a-z0-9][a-z0-9-]*)\s+(?:TEXT|INT|UINT|FLOAT|REGEX|INDEX)", re.M)
ROW = re.compile(r'BadInput\{\s*"((?:[^"\\]|\\.)*)"')


def value_options(binary):
    out = {}
    for command in SUBCOMMANDS:
        text = subprocess.run([binary, command, "--help"], capture_output=True, text=True, check=True).stdout
        out[command] = set(VALUE_OPTION.findall(text))
    return out


def rows(test_source):
    """subcommand -> the argument strings of its bad-input rows."""
    out = {}
    for args in ROW.findall(test_source):
        words = args.split()
        if words and words[0] in SUBCOMMANDS:
            out.setdefault(words[0], []).append(args)
    return out


def problems(options, table):
    found = []
    for command in SUBCOMMANDS:
        if not table.get(command):
            found.append(f"{command}: no bad-input row at all")
        for option in sorted(options.get(command, ())):
            pattern = re.compile(re.escape(option) + r"(?=[ =]|$)")
            if not any(pattern.search(args) for args in table.get(command, [])):
                found.append(f"{command} {option}: no bad-input row gives it a bad value")
    return found


def main():
    binary, source = sys.argv[1], sys.argv[2]
    options = value_options(binary)
    table = rows(open(source).read())
    planted = {c: set(o) for c, o in options.items()}
    planted["run"].add("--planted-option")
    if not any("--planted-option" in p for p in problems(planted, table)):
        print("FAIL: the self-test's planted option without a row was not caught")
        return 1
    found = problems(options, table)
    for p in found:
        print(f"FAIL: {p}")
    if found:
        return 1
    total = sum(len(o) for o in options.values())
    print(f"every value option has a bad-input row: {total} options of {len(SUBCOMMANDS)} subcommands, "
          f"{sum(len(r) for r in table.values())} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
