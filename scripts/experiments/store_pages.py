#!/usr/bin/python3
"""The results store gives the pages the runs' folders give: stores RUN... into a fresh SQLite file and into a
PostgreSQL server started for the purpose (tests/pg_server.py; skipped, said, where it cannot start), then writes
`omnishadow history` and `omnishadow report NEWEST` once from the folders and once from each store (--db), and
compares history.md, history.json and report.html byte for byte. Exit 1 when a page differs.

Usage: scripts/experiments/store_pages.py RUN... [--bin build/release/omnishadow]
"""
import argparse
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests"))
from pg_server import PostgresServer, Unavailable  # noqa: E402


def pages(binary, out, newest, source):
    """history.md, history.json, report.html from `source` (["--history", folder...] or ["--db", url])."""
    os.makedirs(out)
    history_source = source[1:] if source[0] == "--history" else source
    h = subprocess.run([binary, "history", *history_source, "--out", out], capture_output=True, text=True)
    if h.returncode not in (0, 1):
        sys.exit(f"store_pages: history from {source[0]}: {h.stderr.strip()}")
    r = subprocess.run([binary, "report", newest, *source, "--out", os.path.join(out, "report.html")],
                       capture_output=True, text=True)
    if r.returncode:
        sys.exit(f"store_pages: report from {source[0]}: {r.stderr.strip()}")
    return [open(os.path.join(out, name), "rb").read() for name in ("history.md", "history.json", "report.html")]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--bin", default=os.path.join(ROOT, "build", "release", "omnishadow"))
    args = parser.parse_args()
    runs = [os.path.abspath(r) for r in args.runs]
    with tempfile.TemporaryDirectory() as tmp:
        stores = {"sqlite": "sqlite:" + os.path.join(tmp, "runs.db")}
        server = None
        try:
            server = PostgresServer().__enter__()
            stores["postgresql"] = server.url()
        except Unavailable as e:
            print(f"store_pages: PostgreSQL skipped: {e}")
        try:
            folders = pages(args.bin, os.path.join(tmp, "folders"), runs[-1], ["--history", *runs])
            differing = 0
            for name, url in stores.items():
                s = subprocess.run([args.bin, "store", *runs, "--db", url], capture_output=True, text=True)
                if s.returncode:
                    sys.exit(f"store_pages: store into {name}: {s.stderr.strip()}")
                stored = pages(args.bin, os.path.join(tmp, name), runs[-1], ["--db", url])
                for page, a, b in zip(("history.md", "history.json", "report.html"), folders, stored):
                    same = a == b
                    differing += not same
                    print(f"{name}: {page} ({len(a)} bytes) {'equals' if same else 'DIFFERS FROM'} the folders'")
        finally:
            if server:
                server.__exit__(None, None, None)
    sys.exit(1 if differing else 0)


if __name__ == "__main__":
    main()
