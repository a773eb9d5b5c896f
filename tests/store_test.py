#!/usr/bin/python3
"""`omnishadow store` into SQLite and into a real PostgreSQL server started from Debian's packages in a temporary
folder (initdb, pg_ctl, a free local port, a socket in the folder), then stopped. On each: two runs stored, each
case with its status and axes and every measure; storing a run again changes nothing; a second writer waits for the
first (two stores at once both land whole); a results file that cannot be read stores nothing and is one line with
exit 2; a URL that is neither is one line with exit 2. PostgreSQL skips (ctest 77) with its reason where its server
binaries are absent or cannot run here (initdb refuses root, so it runs as the `postgres` user the package makes).

Usage: store_test.py OMNISHADOW
"""
import glob
import json
import os
import resource
import shutil
import signal
import sqlite3
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pg_server import PostgresServer, Unavailable  # noqa: E402

BIN = sys.argv[1]


def sh(args, **kw):
    return subprocess.run(args, capture_output=True, text=True, **kw)


def make_run(tmp, name, extra, images="none"):
    out = os.path.join(tmp, name)
    r = sh([BIN, "run", "--backend", "gl", "--scene", "room", "--technique",
            "six_pass,geometry_shader", "--filter", "hard", "--frames", "2", "--warmup", "0", "--images", images,
            "--check", "--benchmark_repetitions=2", "--out", out] + extra,
           env={**os.environ, "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR", "/tmp")})
    assert r.returncode in (0, 1), f"run {name} failed:\n{r.stderr[-2000:]}"
    return out


def store(db, *runs):
    return sh([BIN, "store", *runs, "--db", db])


def check_store(db, runs, count):
    """Stores the runs, again, and at once from two processes; `count(table)` reads the database."""
    doc = json.load(open(os.path.join(runs[0], "results.json")))
    cases = len(doc["omnishadow"]["cases"])
    r = store(db, runs[0])
    assert r.returncode == 0 and "stored " in r.stdout, r.stdout + r.stderr
    assert count("runs") == 1 and count("cases") == cases, (count("runs"), count("cases"))
    measures = count("measures")
    assert measures >= cases * 2, f"per-repetition times of every case: {measures}"
    assert count("schema_migrations") == 3, "every migration applied, once each"
    assert count("documents") == 1, "the run's results.json kept whole"
    r = store(db, runs[0])
    assert r.returncode == 0 and "already stored" in r.stdout, r.stdout + r.stderr
    assert (count("runs"), count("cases"), count("measures")) == (1, cases, measures), "storing again changed it"
    # Two writers at once: each run lands whole.
    procs = [subprocess.Popen([BIN, "store", run, "--db", db], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for run in runs[1:]]
    for p in procs:
        out, err = p.communicate(timeout=120)
        assert p.returncode == 0, out + err
    assert count("runs") == len(runs), count("runs")
    # A results file that cannot be read: one line, exit 2, nothing stored.
    bad = os.path.join(os.path.dirname(runs[0]), "bad")
    os.makedirs(bad, exist_ok=True)
    open(os.path.join(bad, "results.json"), "w").write('{"omnishadow": {"cases": [')
    r = store(db, bad)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "bad/results.json" in r.stderr, r.stderr
    assert count("runs") == len(runs)
    # A results file of another format version: one line naming the file and the format, nothing stored.
    older = os.path.join(os.path.dirname(runs[0]), "older")
    os.makedirs(older, exist_ok=True)
    doc["omnishadow"]["format"] = "omnishadow-results/0"
    json.dump(doc, open(os.path.join(older, "results.json"), "w"))
    r = store(db, older)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "older/results.json: /omnishadow/format is " \
        '"omnishadow-results/0", not omnishadow-results/1' in r.stderr, r.stderr
    assert count("runs") == len(runs)


def check_full_disk(tmp, runs):
    """A disk that fills during a store (the file size limit, RLIMIT_FSIZE, with SIGXFSZ ignored, as a full disk
    answers a write: EFBIG): one line, exit 2, and the database as it was, the run not in it by half."""
    path = os.path.join(tmp, "db", "full.db")
    db = "sqlite:" + path
    r = store(db, runs[0])
    assert r.returncode == 0, r.stderr
    with sqlite3.connect(path) as c:
        before = [c.execute(f"SELECT COUNT(*) FROM {t}").fetchone()[0] for t in ("runs", "cases", "measures")]
    limit = os.path.getsize(path) + 4096  # room for the journal's start, not for the run's rows

    def limited():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    r = subprocess.run([BIN, "store", runs[1], "--db", db], capture_output=True, text=True, preexec_fn=limited)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "not stored in" in r.stderr, \
        f"exit {r.returncode}: {r.stdout}{r.stderr}"
    with sqlite3.connect(path) as c:
        after = [c.execute(f"SELECT COUNT(*) FROM {t}").fetchone()[0] for t in ("runs", "cases", "measures")]
        integrity = c.execute("PRAGMA integrity_check").fetchone()[0]
    assert after == before and integrity == "ok", f"the full disk left {after} (was {before}), {integrity}"
    print(f"sqlite: a disk full at {limit} bytes: {r.stderr.strip()}")


def history_runs(tmp):
    """Four commits of one small matrix, a day apart: c1 and c2 alike; c3 with a planted accuracy regression (every
    cube lookup moved by half a texel, --lookup-perturb 0.5: the ids stay, the shadows and images change, and the
    lookup check fails six_pass: ok -> failed_check); c4 the same shadows held to the default error bound (5%)
    instead of 100%: geometry_shader ok -> failed_quality."""
    folder = os.path.join(tmp, "history")
    lenient, perturbed = ["--max-error", "100"], ["--lookup-perturb", "0.5"]
    for i, extra in enumerate([lenient, lenient, lenient + perturbed, perturbed], 1):
        run = make_run(folder, f"c{i}", ["--cube", "16", "--frame", "32x24"] + extra, images="all")
        path = os.path.join(run, "results.json")
        doc = json.load(open(path))
        doc["omnishadow"].update(commit=f"c{i}", commit_date=f"2026-11-0{i}T00:00:00+00:00")
        json.dump(doc, open(path, "w"))
    return folder


def check_history(db, folder, tmp):
    """history --db and report --db give the pages the same runs' folders give; the planted step is on them."""
    r = store(db, *sorted(glob.glob(os.path.join(folder, "c*"))))
    assert r.returncode == 0, r.stderr
    pages = {}
    for name, source in (("folders", [folder]), ("db", ["--db", db])):
        out = os.path.join(tmp, f"history-{name}")
        h = sh([BIN, "history", *source, "--out", out, "--accepted", os.path.join(tmp, "no-accepted.json")])
        assert h.returncode == 1, f"history from {name}: the planted step alerts (exit 1): {h.stdout}{h.stderr}"
        page = os.path.join(tmp, f"report-{name}.html")
        rep = sh([BIN, "report", os.path.join(folder, "c3"), "--out", page] +
                 (["--history", folder] if name == "folders" else ["--db", db]))
        assert rep.returncode == 0, rep.stderr
        pages[name] = [open(os.path.join(out, "history.md")).read(), open(os.path.join(out, "history.json")).read(),
                       open(page).read()]
    alerts = json.loads(pages["db"][1])["alerts"]
    planted = [a for a in alerts if a["commit"] == "c3" and a["metric"] == "misclassified_percent"]
    assert len({a["case"] for a in planted}) == 2, f"the accuracy step at c3, both cases: {alerts}"
    assert any(a["metric"].startswith("image_") and a["commit"] == "c3" for a in alerts), \
        f"the images' step at c3, from the hashes the store kept: {alerts}"
    for i, what in enumerate(("history.md", "history.json", "report.html")):
        assert pages["folders"][i] == pages["db"][i], f"{what} from the store differs from the folders'"
    return len(alerts)


def check_migration_from_schema_1(tmp, runs):
    """A store written at schema 1 (the first binary's: the state of a newer store without the later migrations'
    tables and rows) is migrated by the next fetch; its old runs have no document until stored again, and say so."""
    path = os.path.join(tmp, "db", "schema1.db")
    r = store("sqlite:" + path, runs[0])
    assert r.returncode == 0, r.stderr
    with sqlite3.connect(path) as c:
        c.executescript("DROP TABLE documents; DROP TABLE images; DROP TABLE thresholds; DROP TABLE accepted_steps; "
                        "DELETE FROM schema_migrations WHERE version >= 2;")
    fetched = os.path.join(tmp, "fetched-schema1")
    r = sh([BIN, "fetch", "--db", "sqlite:" + path, "--out", fetched])
    assert r.returncode == 0 and "fetched 0 runs" in r.stdout and "1 stored run(s) have no document" in r.stdout, \
        r.stdout + r.stderr
    with sqlite3.connect(path) as c:
        versions = [v for (v,) in c.execute("SELECT version FROM schema_migrations ORDER BY version")]
    assert versions == [1, 2, 3], f"fetch migrates an old store first: {versions}"
    r = store("sqlite:" + path, runs[0])
    assert r.returncode == 0 and "its document and" in r.stdout, r.stdout + r.stderr
    shutil.rmtree(fetched)
    r = sh([BIN, "fetch", "--db", "sqlite:" + path, "--out", fetched])
    assert r.returncode == 0 and "fetched 1 runs" in r.stdout, r.stdout + r.stderr
    assert json.load(open(os.path.join(fetched, os.path.basename(runs[0]), "results.json"))) == \
        json.load(open(os.path.join(runs[0], "results.json"))), "the fetched run is the stored one"


def alerts(db, out):
    r = sh([BIN, "alerts", "--db", db, "--out", out])
    assert r.returncode in (0, 1), r.stdout + r.stderr
    found = {(a["metric"], a["previous_commit"], a["commit"], a["regression"]): a for a in
             json.load(open(os.path.join(out, "alerts.json")))["alerts"]}
    assert (r.returncode == 1) == bool(found), f"alerts exit 1 exactly when there are some: {r.returncode} {found}"
    return {k[:3]: k[3] for k in found}, r.stdout


def check_alerts(db, tmp):
    """alerts lists the steps not yet accepted with their commit ranges: the planted accuracy regression at c3
    and the status regressions at c3 and c4; a threshold in the store (a fixed 50% on misclassified pixels) and
    accepted steps in the store silence them."""
    found, page = alerts(db, os.path.join(tmp, "alerts-1"))
    assert found.get(("misclassified_percent", "c2", "c3")) is True, f"the accuracy regression, c2..c3: {found}"
    assert found.get(("status", "c3", "c4")) is True, f"the status regression ok -> failed_quality, c3..c4: {found}"
    assert {k[0] for k in found if k[2] == "c4"} == {"status"}, f"c4 changed the statuses only: {found}"
    assert ("image_lit", "c2", "c3") in found, found
    assert "| c2..c3 |" in page and "| ok | failed_quality |" in page, page
    r = sh([BIN, "threshold", "--db", db, "--metric", "^misclassified_percent$", "--percent", "50"])
    assert r.returncode == 0, r.stderr
    found, _ = alerts(db, os.path.join(tmp, "alerts-2"))
    assert ("misclassified_percent", "c2", "c3") not in found, f"+19% is under the store's 50% threshold: {found}"
    assert ("status", "c3", "c4") in found, found
    for metric, commit in (("status", "c3"), ("status", "c4"), ("image_", "c3")):
        r = sh([BIN, "accept", "--db", db, "--case", "room", "--metric", metric, "--commit", commit, "--reason", "planted"])
        assert r.returncode == 0, r.stderr
    found, page = alerts(db, os.path.join(tmp, "alerts-3"))
    assert not found and "0 not accepted" in page, f"every step accepted or under its threshold: {found}"


def sqlite_part(tmp, runs):
    path = os.path.join(tmp, "db", "omnishadow.db")
    db = "sqlite:" + path

    def count(table):
        with sqlite3.connect(path) as c:
            return c.execute(f"SELECT COUNT(*) FROM {table}").fetchone()[0]

    # The first store creates the folder and the file, and migrates.
    check_store(db, runs, count)
    with sqlite3.connect(path) as c:
        statuses = dict(c.execute("SELECT case_id, status FROM cases WHERE case_id LIKE '%six_pass%'").fetchall())
        axes = json.loads(c.execute("SELECT axes FROM cases LIMIT 1").fetchone()[0])
        metrics = {m for (m,) in c.execute("SELECT DISTINCT metric FROM measures")}
    assert statuses and set(statuses.values()) <= {"ok", "failed_quality"}, statuses
    assert axes["scene"] == "room", axes
    assert {"frame_ms", "frame_cpu_ms", "accuracy.misclassified_percent", "timing.frame_wall_ms.median",
            "timing.shadow.cpu_wall_ms.p90", "device_state.clock_mhz"} <= metrics, metrics
    # A writer holding the database: the store waits for it (it has not ended, with an error or a run stored,
    # while the lock is held), then lands once the lock is let go. A slow machine only makes the wait shorter
    # than the test's patience; no outcome rests on the clock.
    holder = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    extra = make_run(tmp, "third", ["--cube", "16", "--frame", "32x24", "--pcf-scale", "2"])
    holder.execute("BEGIN EXCLUSIVE")
    waiting = subprocess.Popen([BIN, "store", extra, "--db", db], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    try:
        out, err = waiting.communicate(timeout=2)
        raise AssertionError(f"the store ended while another writer held the database: {out}{err}")
    except subprocess.TimeoutExpired:
        pass
    # A lock held longer than a store will wait (?timeout=1): one line naming the database, exit 2, nothing stored.
    r = store(db + "?timeout=1", runs[0])
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "database is locked" in r.stderr, r.stderr
    holder.execute("ROLLBACK")
    out, err = waiting.communicate(timeout=120)
    assert waiting.returncode == 0, err
    assert count("runs") == len(runs) + 1
    print(f"sqlite: {count('runs')} runs, {count('cases')} cases, {count('measures')} measures")
    check_migration_from_schema_1(tmp, runs)
    check_full_disk(tmp, runs)
    db = "sqlite:" + os.path.join(tmp, "db", "history.db")
    count = check_history(db, history_runs(tmp), tmp)
    check_alerts(db, tmp)
    print(f"sqlite: history and report from the store equal the folders' ({count} alerts); alerts, thresholds, "
          "accepted steps")


def postgresql_part(tmp, runs):
    try:
        server = PostgresServer().__enter__()
    except Unavailable as e:
        return str(e)
    try:
        db = server.url()

        def count(table):
            return int(server.psql(f"SELECT COUNT(*) FROM {table}"))

        check_store(db, runs, count)
        print(f"postgresql: {count('runs')} runs, {count('cases')} cases, {count('measures')} measures")
        server.psql("CREATE DATABASE history")
        history_db = server.url("history")
        alerts_count = check_history(history_db, os.path.join(tmp, "history"), tmp)
        check_alerts(history_db, tmp)
        print(f"postgresql: history and report from the store equal the folders' ({alerts_count} alerts); alerts, "
              "thresholds, accepted steps")
    finally:
        server.__exit__(None, None, None)
    return None


def main():
    r = store("mysql://localhost/x", "/nonexistent")
    assert r.returncode == 2 and "not sqlite:PATH or postgresql://" in r.stderr, r.stderr
    with tempfile.TemporaryDirectory() as tmp:
        small = ["--cube", "16", "--frame", "32x24"]
        runs = [make_run(tmp, "first", small), make_run(tmp, "second", ["--cube", "32", "--frame", "32x24"]),
                make_run(tmp, "fourth", ["--cube", "16", "--frame", "48x32"])]
        sqlite_part(tmp, runs)
        skipped = postgresql_part(tmp, runs)
    if skipped:
        print(f"SKIP: PostgreSQL: {skipped} (SQLite passed)")
        sys.exit(77)
    print("store: SQLite and PostgreSQL hold every run whole, once")


if __name__ == "__main__":
    main()
