#!/usr/bin/python3
"""Every option of every subcommand is documented once, in docs/guide.md's option tables, and no table names an
option the CLI does not have.

The CLI's own help is the source: `omnishadow SUBCOMMAND --help` lists each option (CLI11). docs/guide.md holds a
table per group, each after a marker line `<!-- options: NAME -->`; an option is documented where its row's first
cell names it in backticks (`--cube`). A subcommand reads the groups OPTION_GROUPS gives it: an option it has must be
in exactly one of them, and every option a group names must belong to some subcommand that reads that group.
A self-test plants an undocumented option and a stale row and shows both are caught.

Usage: options_documented_test.py OMNISHADOW GUIDE
"""
import re
import subprocess
import sys

# The groups of docs/guide.md each subcommand reads: options the device-opening subcommands share are in `common`.
OPTION_GROUPS = {
    "list": ["common"],
    "run": ["common", "run"],
    "compare": ["compare"],
    "merge": [],
    "report": ["report"],
    "device-key": [],
    "store": ["store"],
    "fetch": ["fetch"],
    "history": ["history"],
    "alerts": ["alerts"],
    "accept": ["accept"],
    "threshold": ["threshold"],
    "export": ["export"],
}
HELP_OPTION = re.compile(r"^\s+(?:-\w,)?(--[a-z0-9][a-z0-9-]*)", re.M)
MARKER = re.compile(r"^<!-- options: ([a-z-]+) -->$")
ROW_OPTION = re.compile(r"`(--[a-z0-9][a-z0-9-]*)")


def cli_options(binary):
    out = {}
    for command in OPTION_GROUPS:
        text = subprocess.run([binary, command, "--help"], capture_output=True, text=True, check=True).stdout
        out[command] = set(HELP_OPTION.findall(text)) - {"--help"}
    return out


def documented(guide_text):
    """group -> list of options named in the first cell of its table's rows (duplicates kept)."""
    groups, group, in_table = {}, None, False
    for line in guide_text.splitlines():
        marker = MARKER.match(line.strip())
        if marker:
            group, in_table = marker.group(1), False
            groups.setdefault(group, [])
            continue
        if group is None:
            continue
        if line.startswith("|"):
            in_table = True
            first = line.split("|")[1]
            groups[group] += ROW_OPTION.findall(first)
        elif in_table:
            group, in_table = None, False  # the table ended
    return groups


def problems(cli, groups):
    found = []
    for command, options in sorted(cli.items()):
        for option in sorted(options):
            where = [g for g in OPTION_GROUPS[command] for o in groups.get(g, []) if o == option]
            if not where:
                found.append(f"{command} {option}: not in docs/guide.md's tables {OPTION_GROUPS[command]}")
            elif len(where) > 1:
                found.append(f"{command} {option}: documented {len(where)} times ({', '.join(where)})")
    for group, options in sorted(groups.items()):
        readers = [c for c, gs in OPTION_GROUPS.items() if group in gs]
        if not readers:
            found.append(f"table '{group}': no subcommand reads it (OPTION_GROUPS)")
        for option in options:
            if not any(option in cli[c] for c in readers):
                found.append(f"table '{group}' names {option}, which no subcommand reading it has")
    return found


def self_test(cli, groups):
    planted = {c: set(o) for c, o in cli.items()}
    planted["run"].add("--planted-undocumented")
    stale = {g: list(o) for g, o in groups.items()}
    stale["run"] = stale.get("run", []) + ["--planted-stale"]
    caught = problems(planted, groups), problems(cli, stale)
    return any("--planted-undocumented" in p for p in caught[0]) and any("--planted-stale" in p for p in caught[1])


def main():
    binary, guide = sys.argv[1], sys.argv[2]
    cli = cli_options(binary)
    groups = documented(open(guide).read())
    if not self_test(cli, groups):
        print("FAIL: the self-test's planted undocumented option or stale row was not caught")
        return 1
    found = problems(cli, groups)
    for p in found:
        print(f"FAIL: {p}")
    if found:
        return 1
    total = sum(len(o) for o in cli.values())
    print(f"every option documented once: {total} options of {len(cli)} subcommands, {len(groups)} tables")
    return 0


if __name__ == "__main__":
    sys.exit(main())
