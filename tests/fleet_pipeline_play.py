#!/usr/bin/python3
"""Plays the GPU fleet's pipelines end to end over two commits of a scratch repository, on llvmpipe:
.gitlab-ci.yml with gitlab-ci-local (shell executor, each job in its own copy of the tree), and the GitHub
workflow's jobs with tests/github_actions_player.py. Commit A (main, a small fleet matrix) has no baseline: both
pipelines pass and say so on the page. Its merged GitLab run becomes the fleet baseline as docs/regressions.md documents
(scripts/ci/fleet_baseline.sh with a gate; commit B). Commit C (a branch) injects fragment work in every case (the
scripted clock times it: 1 ms frames become 2 ms on any machine) and plants a bug that makes the geometry-shader case fail its checks: both merge-request pipelines build it, and their
compare step fails (exit 1) with a summary naming the slowed case and the failed one; GitLab's merge-request note
is posted (to a stand-in curl). A RenderDoc trace in results/traces/ is replayed by the first shard and kept in
the baseline at B; C captures it again with a planted bug, and both fan-ins name its changed image. A PostgreSQL server started for the play (tests/pg_server.py) is the results store
(OMNISHADOW_STORE_URL) of the GitLab pipelines: A's merged run is stored, C's merge-request run is not, and C's
comparison takes its baseline from the store (A's run, the newest stored on the merge-base's line) with the gate
committed at B; GitHub's play at C has no store and reads B's git baseline. Where the server cannot start here the
play goes on without a store and says why. Skips (ctest 77) with the reason where gitlab-ci-local cannot be
installed from npm, or OpenGL is unavailable. Slow (four builds, ccache shares their compilations): not run under
the sanitizers."""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    import yaml
    from github_actions_player import Player
    from pg_server import PostgresServer, Unavailable
except ImportError as e:
    print(f"SKIP: needs python3-yaml (Debian package; scripts/setup.sh installs it): {e}")
    sys.exit(77)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("OMNISHADOW_BIN", os.path.join(ROOT, "build", "release", "omnishadow"))
TOOLS = os.environ.get("OMNISHADOW_TOOLS_DIR", os.path.join(ROOT, "build", "tools"))
GITLAB_CI_LOCAL = "4.60.0"  # the newest release that runs on Debian 12's Node.js 20 (4.75 needs Node 22)
DEVICE = "nvidia-h100"      # the device block of .gitlab-ci.yml / gpu-fleet.yml the play runs (tags are not honoured)
# The play's fleet matrix: two cases, one per shard, 8 repetitions as the fleet runs them, on the scripted clock
# (--inject-frame-ms, bench/run/scripted_clock.h): every frame lasts 1 ms on every clock the harness reads, 1% more
# per unit of injected fragment work, so commit C's slowdown is +100% exactly and its verdict the same on any
# machine, however loaded. Images and checks are rendered as usual.
PLAY_MATRIX = """# the play's fleet matrix: two cases, one per shard, 8 repetitions, frames timed by the scripted clock
--backend
gl
--scene
room
--cube
64
--frame
160x120
--technique
six_pass,geometry_shader
--filter
hard
--frames
3
--warmup
1
--benchmark_repetitions=8
--benchmark_enable_random_interleaving=true
--inject-frame-ms
1
"""
SLOWED, FAILED = "gl/room/c64/f160x120/six_pass/hard", "gl/room/c64/f160x120/geometry_shader/hard"
GATE = {"metric": "cpu", "alpha": 0.01, "min_effect": 0.1}
TRACE = os.path.join("results", "traces", "room.rdc")  # the play's fleet trace; commit C re-captures it with a bug


def skip(reason):
    print(f"SKIP: {reason}")
    sys.exit(77)


def sh(cmd, cwd, env=None, timeout=1800):
    return subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=timeout)


def gitlab_ci_local():
    prefix = os.path.join(TOOLS, f"gitlab-ci-local-{GITLAB_CI_LOCAL}")
    exe = os.path.join(prefix, "node_modules", ".bin", "gitlab-ci-local")
    if os.path.exists(exe):
        return exe
    if not shutil.which("npm"):
        skip("npm is not installed (Debian's npm package), so gitlab-ci-local cannot be installed")
    r = sh(["npm", "install", "--prefix", prefix, "--no-audit", "--no-fund", f"gitlab-ci-local@{GITLAB_CI_LOCAL}"],
           ROOT, timeout=900)
    if r.returncode:
        lines = [line for line in r.stdout.splitlines() if line.strip()]
        if re.search(r"ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ETIMEDOUT|ECONNRESET|ENETUNREACH|network", r.stdout):
            skip("the npm registry is unreachable: " + (lines[-1] if lines else "npm failed"))
        raise AssertionError("npm install gitlab-ci-local failed:\n" + r.stdout[-3000:])
    return exe


def git(repo, *args):
    r = sh(["git", "-c", "user.name=fleet play", "-c", "user.email=play@localhost", *args], repo)
    assert r.returncode == 0, f"git {' '.join(args)}: {r.stdout}"
    return r.stdout.strip()


def edit(repo, path, old, new):
    full = os.path.join(repo, path)
    with open(full) as f:
        text = f.read()
    assert text.count(old) == 1, f"{path}: expected one '{old}' to plant the play's change (the source moved on?)"
    with open(full, "w") as f:
        f.write(text.replace(old, new))


def capture_trace(work, name, *extra):
    """A RenderDoc capture of a small GL case (the play's fleet trace), or None where RenderDoc is missing here."""
    out = os.path.join(work, name)
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    sh([BIN, "run", "--backend", "gl", "--scene", "room", "--cube", "32", "--frame", "64x48", "--technique",
        "six_pass", "--filter", "hard", "--frames", "1", "--warmup", "0", "--benchmark_repetitions=1", "--images",
        "none", "--capture", "all", "--out", out, *extra], ROOT, env)
    found = glob.glob(os.path.join(out, "captures", "*.rdc"))
    return found[0] if found else None


def scratch_repository(work):
    """Commit A: this work tree (tracked and unignored files) with the play's small fleet matrix, on main."""
    repo = os.path.join(work, "repo")
    files = sh(["git", "ls-files", "-co", "--exclude-standard", "-z"], ROOT).stdout.split("\0")
    for f in filter(None, files):
        if os.path.isfile(os.path.join(ROOT, f)):
            os.makedirs(os.path.dirname(os.path.join(repo, f)), exist_ok=True)
            shutil.copy2(os.path.join(ROOT, f), os.path.join(repo, f))
    with open(os.path.join(repo, "scripts", "ci", "fleet_matrix.args"), "w") as f:
        f.write(PLAY_MATRIX)
    # A trace kept as a case of the fleet (results/traces/): its replays and image go into the baseline at B.
    trace = capture_trace(work, "trace-a")
    assert trace or not shutil.which("renderdoccmd"), "RenderDoc is installed here but captured no trace"
    if trace:
        os.makedirs(os.path.join(repo, "results", "traces"), exist_ok=True)
        shutil.copy2(trace, os.path.join(repo, TRACE))
    else:
        print("fleet pipeline play: no trace replayed (RenderDoc's capture failed or is missing here)")
    git(repo, "init", "-q", "-b", "main")
    with open(os.path.join(repo, ".git", "info", "exclude"), "a") as f:
        f.write(".gitlab-ci-local/\n")
    git(repo, "add", "-A")
    git(repo, "commit", "-q", "-m", "A: the play's fleet matrix")
    return repo


def play_gitlab(exe, repo, env, variables):
    args = [exe, "--shell-isolation", "--concurrency", "1", "--no-artifacts-to-source", "--needs", f"merge:{DEVICE}"]
    for v in variables:
        args += ["--variable", v]
    r = sh(args, repo, env)
    merged = glob.glob(os.path.join(repo, ".gitlab-ci-local", "artifacts", f"merge*{DEVICE}", "fleet", "merged"))
    summary = os.path.join(merged[0], "compare", "summary.md") if merged else ""
    return r, merged[0] if merged else None, open(summary).read() if os.path.exists(summary) else ""


def play_github(repo, sha, work, event, base_ref, env):
    caller = yaml.safe_load(open(os.path.join(repo, ".github", "workflows", "gpu-fleet.yml")))
    call = caller["jobs"][DEVICE]
    assert call["uses"] == "./.github/workflows/fleet-device.yml", call
    reusable = yaml.safe_load(open(os.path.join(repo, ".github", "workflows", "fleet-device.yml")))
    player = Player(reusable, repo, sha, event, work, base_ref)
    saved = dict(os.environ)
    os.environ.update(env)
    try:
        player.play(call["with"])
    finally:
        os.environ.clear()
        os.environ.update(saved)
    return player


def check_regressions(merged, summary, where):
    """The fan-in failed for both planted changes, under the gate committed with the baseline at the merge-base."""
    assert re.search(re.escape(SLOWED) + r"[^\n]*\*\*regression\*\*", summary), f"{where}: the slowed case is not named:\n{summary}"
    assert re.search(re.escape(FAILED) + r"[^\n]*: ok -> failed", summary), f"{where}: the failed case is not named:\n{summary}"
    with open(os.path.join(merged, "compare", "comparison.json")) as f:
        comparison = json.load(f)
    assert comparison["failed"] is True, f"{where}: the comparison did not fail"
    assert {k: comparison[k] for k in GATE} == GATE, f"{where}: the baseline's gate was not applied: {comparison}"
    slowed = [c for c in comparison["cases"] if c["id"].startswith(SLOWED + "/")]
    assert slowed and slowed[0]["regressed"], f"{where}: the slower case does not fail the comparison: {slowed}"
    assert (slowed[0]["base_ms"], slowed[0]["new_ms"]) == (1.0, 2.0), \
        f"{where}: not the scripted clock's 1 ms against 2 ms (CPU ms per frame): {slowed[0]}"
    assert any(line.startswith(FAILED + "/") for line in comparison["status_regressions"]), comparison


def check_trace(summary, bugged, where):
    """The re-captured trace's replayed image differs from the baseline's: a regression the summary names."""
    if bugged:
        assert re.search(r"`replay/room` [^\n]*\*\*image changed\*\*", summary), \
            f"{where}: the changed trace image is not named:\n{summary}"


def main():
    r = sh([BIN, "list"], ROOT, dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp")))
    if "gl: unavailable" in r.stdout:
        skip("OpenGL backend unavailable here: " + next(l for l in r.stdout.splitlines() if "gl: unavailable" in l))
    exe = gitlab_ci_local()
    work = tempfile.mkdtemp(prefix="fleet-pipeline-play-")
    server = None
    try:
        try:
            server = PostgresServer().__enter__()
        except Unavailable as e:
            print(f"fleet pipeline play: no results store (its PostgreSQL cannot start here: {e})")
        run_plays(exe, work, server)
    finally:
        if server:
            server.__exit__(None, None, None)
        if os.environ.get("KEEP_PLAY"):
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)


def stored_commits(server):
    """The commits of the runs the store holds (none without a store)."""
    return server.psql("SELECT commit_sha FROM runs ORDER BY commit_sha").split() if server else []


def run_plays(exe, work, server):
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    env.pop("OMNISHADOW_BIN", None)  # the pipelines use their own build jobs' binaries
    if shutil.which("ccache"):  # the four builds of two commits share compilations (absolute paths made relative)
        env.update(CMAKE_CXX_COMPILER_LAUNCHER="ccache", CCACHE_DIR=os.path.join(TOOLS, "ccache"),
                   CCACHE_BASEDIR=work, CCACHE_NOHASHDIR="true")
    # A stand-in curl on PATH records the merge-request note GitLab's fan-in posts.
    fake = os.path.join(work, "bin")
    os.makedirs(fake)
    with open(os.path.join(fake, "curl"), "w") as f:
        f.write(f'#!/bin/sh\nprintf "%s\\n" "$@" >> "{work}/curl.log"\n')
    os.chmod(os.path.join(fake, "curl"), 0o755)
    env["PATH"] = fake + os.pathsep + env["PATH"]
    repo = scratch_repository(work)
    a = git(repo, "rev-parse", "HEAD")

    store = [f"OMNISHADOW_STORE_URL={server.url()}"] if server else []

    # Commit A on main: no baseline yet. Both pipelines pass and say so where the engine shows it; GitLab's merged
    # run goes into the store.
    r, merged, summary = play_gitlab(exe, repo, env, ["CI_COMMIT_BRANCH=main", "CI_DEFAULT_BRANCH=main"] + store)
    assert r.returncode == 0 and merged, f"GitLab pipeline at A failed:\n{r.stdout[-6000:]}"
    assert "No baseline for this device key" in summary, f"GitLab at A: no word on the missing baseline:\n{summary}"
    assert stored_commits(server) == ([a[:12]] if server else []), f"A's merged run stored once: {stored_commits(server)}"
    gh = play_github(repo, a, os.path.join(work, "github-a"), "push", "", env)
    assert set(gh.results.values()) == {"success"}, f"GitHub play at A: {gh.results}\n" + "\n".join(gh.logs.values())[-6000:]
    assert "No baseline for this device key" in gh.summaries["merge"], gh.summaries

    # Commit B on main: the documented bootstrap, from the GitLab pipeline's merged artifact, with a timing gate.
    gate = os.path.join(work, "gate.json")
    with open(gate, "w") as f:
        json.dump(GATE, f)
    built = glob.glob(os.path.join(repo, ".gitlab-ci-local", "artifacts", f"build*{DEVICE}", "fleet-build", "bin", "omnishadow"))
    r = sh(["bash", "scripts/ci/fleet_baseline.sh", merged, "--gate", gate], repo, dict(env, OMNISHADOW_BIN=built[0]))
    assert r.returncode == 0, f"fleet_baseline.sh: {r.stdout}"
    key = re.search(r"device key (\S+):", r.stdout).group(1)
    stored = os.path.join(repo, "results", "fleet_baselines", key)
    traces = os.path.exists(os.path.join(repo, TRACE))
    for name in ("results.json", "gate.json", "fleet_matrix.args") + (("replay.json",) if traces else ()):
        assert os.path.exists(os.path.join(stored, name)), f"the fleet baseline lacks {name}"
    assert glob.glob(os.path.join(stored, "images", "**", "lit.png"), recursive=True), "the fleet baseline has no images"
    git(repo, "add", "-A")
    git(repo, "commit", "-q", "-m", f"B: fleet baseline for {key}")
    b = git(repo, "rev-parse", "HEAD")

    # Commit C on a branch: more fragment work in every case, and the geometry-shader technique's +Z face written
    # into the -Z layer (its checks fail). Merge-request pipelines against main.
    git(repo, "checkout", "-q", "-b", "slower-and-broken")
    edit(repo, "bench/run/matrix.h", "std::vector<int> injected_work{0};", "std::vector<int> injected_work{100};")
    edit(repo, "shaders/shadow_depth.geom", "gl_Layer = face;  // per vertex", "gl_Layer = face == 4 ? 5 : face;  // per vertex")
    bugged = capture_trace(work, "trace-c", "--lookup-perturb", "0.5") if traces else None
    if bugged:  # the trace captured again where a planted bug shows: its replayed image changes
        shutil.copy2(bugged, os.path.join(repo, TRACE))
    git(repo, "commit", "-q", "-am", "C: slower, and the geometry shader's layers wrong")
    c = git(repo, "rev-parse", "HEAD")
    r, merged, summary = play_gitlab(exe, repo, env, [
        "CI_PIPELINE_SOURCE=merge_request_event", "CI_MERGE_REQUEST_TARGET_BRANCH_NAME=main",
        "CI_MERGE_REQUEST_IID=7", "CI_COMMIT_BRANCH=slower-and-broken", "CI_DEFAULT_BRANCH=main",
        "FLEET_GITLAB_TOKEN=play-token", "CI_API_V4_URL=http://gitlab.invalid/api/v4", "CI_PROJECT_ID=42"] + store)
    assert r.returncode != 0, f"GitLab pipeline at C passed:\n{r.stdout[-6000:]}"
    assert re.search(rf"FAIL\s+merge:{DEVICE}", r.stdout) and re.search(rf"PASS\s+build:{DEVICE}", r.stdout), r.stdout[-4000:]
    if server:
        assert f"against the stored run of {a} (OMNISHADOW_STORE_URL), merge-base {b[:12]}" in r.stdout, \
            "GitLab at C: not compared with A's stored run"
        assert stored_commits(server) == [a[:12]], f"a merge request's run is not stored: {stored_commits(server)}"
    else:
        assert f"at merge-base {b[:12]}" in r.stdout, "GitLab at C: not compared with the baseline at the merge-base"
    check_regressions(merged, summary, "GitLab at C")
    check_trace(summary, bugged, "GitLab at C")
    with open(os.path.join(work, "curl.log")) as f:
        posted = f.read()
    assert "merge_requests/7/notes" in posted and SLOWED in posted, f"no merge-request note posted:\n{posted[-2000:]}"
    gh = play_github(repo, c, os.path.join(work, "github-c"), "pull_request", "main", env)
    assert gh.results == {"build": "success", "bench": "success", "merge": "failure"}, \
        f"GitHub play at C: {gh.results}\n" + gh.logs.get("merge", "")[-6000:]
    assert f"at merge-base {b[:12]}" in gh.logs["merge"], gh.logs["merge"][-3000:]
    assert "fleet_compare.sh merged\n" in gh.logs["merge"] and "(exit 1)" in gh.logs["merge"], \
        "GitHub at C: the compare step did not exit 1 (a regression), as opposed to 2 (an input error)"
    check_regressions(os.path.join(work, "github-c", "jobs", "merge", "merged"), gh.summaries["merge"], "GitHub at C")
    check_trace(gh.summaries["merge"], bugged, "GitHub at C")
    print(f"fleet pipeline play: A {a[:8]} no baseline (both pass, said on the page); baseline B {b[:8]} for {key}; "
          f"C {c[:8]}: GitLab and GitHub fan-ins exit 1 naming {SLOWED} (slower) and {FAILED} (failed checks); "
          "the merge-request note posted" + ("; GitLab stored A's run and compared C with it" if server else "") +
          ("; both named the re-captured trace's changed image" if bugged else "; no trace (RenderDoc missing)"))


if __name__ == "__main__":
    try:
        main()
    except AssertionError as e:
        sys.exit(f"fleet_pipeline_play: {e}")
