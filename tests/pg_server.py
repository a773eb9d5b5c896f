"""A PostgreSQL server from Debian's packages in a temporary folder, for the tests that store into one
(store_test.py, fleet_pipeline_play.py): initdb, pg_ctl on a free local port with its socket in the folder, trust
authentication for the user `omnishadow`, stopped and removed on exit. initdb and postgres refuse root, so as root
they run as the `postgres` user the package makes. Not started: Unavailable with the reason (the package missing, no
user to run it as, initdb failing here)."""
import glob
import os
import shutil
import socket
import subprocess
import tempfile


class Unavailable(Exception):
    pass


def _sh(args):
    return subprocess.run(args, capture_output=True, text=True)


class PostgresServer:
    def __enter__(self):
        bins = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
        if not bins:
            raise Unavailable("no PostgreSQL server binaries (Debian package postgresql; scripts/setup.sh installs it)")
        self.bindir = os.path.dirname(bins[-1])
        self.as_user = []
        if os.geteuid() == 0:
            if not shutil.which("runuser") or _sh(["id", "postgres"]).returncode:
                raise Unavailable("running as root without a postgres user to run the server as")
            self.as_user = ["runuser", "-u", "postgres", "--"]
        self.folder = tempfile.mkdtemp(prefix="omnishadow-pg-")
        os.chmod(self.folder, 0o777)
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        r = _sh(self.as_user + [f"{self.bindir}/initdb", "-D", f"{self.folder}/data", "-U", "omnishadow", "--auth",
                                "trust"])
        if r.returncode:
            self._remove()
            raise Unavailable("initdb failed here: " + (r.stderr.strip().splitlines() or ["?"])[-1])
        r = _sh(self.as_user + [f"{self.bindir}/pg_ctl", "-D", f"{self.folder}/data", "-l", f"{self.folder}/log", "-w",
                                "-o", f"-p {self.port} -k {self.folder} -c listen_addresses=''", "start"])
        if r.returncode:
            log = open(f"{self.folder}/log").read()[-500:]
            self._remove()
            raise Unavailable("pg_ctl start failed: " + log)
        return self

    def url(self, database="postgres"):
        return f"postgresql:///{database}?host={self.folder}&port={self.port}&user=omnishadow"

    def psql(self, sql, database="postgres"):
        """One statement's rows as psql prints them unaligned (-tA); raises on an error."""
        r = _sh([f"{self.bindir}/psql", "-h", self.folder, "-p", str(self.port), "-U", "omnishadow", "-d", database,
                 "-tAc", sql])
        assert r.returncode == 0, r.stderr
        return r.stdout.strip()

    def _remove(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def __exit__(self, *exc):
        _sh(self.as_user + [f"{self.bindir}/pg_ctl", "-D", f"{self.folder}/data", "-m", "immediate", "stop"])
        self._remove()
        return False
