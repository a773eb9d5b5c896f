#!/usr/bin/python3
"""The mutation suite: do the harness's own checks catch a broken shadow pipeline? A benchmark of the checks, not a
unit test: no unit test and no committed baseline takes part, only what a user profiling their own scene has.

For each mutant (a one-place change to the shadow pipeline: a face's up vector, two faces swapped, the face
projection's field of view, the bias, the stored depth's divide by far, the lookup direction's sign on one axis,
the PCF kernels' size) the script applies the change to a scratch clone of this commit, builds it, runs the
default scenes with `--check` on GL and Vulkan, and records whether the run failed, which checks failed and their
figures. Target: every mutant caught (a survivor is a hole in the checks to close, never a row to delete).

With --replay-captures each mutant's build also runs one small case per API with `--check --capture failed
--capture-tool renderdoc`, and the capture its failed check leaves is replayed without the harness
(scripts/replay_renderdoc.py): the bug travels in the trace when the replayed image is the mutant's own, bit for
bit, and differs from the unmutated build's image of the same case (a driver team would see the bug).

Writes OUT/mutants.json and OUT/mutants.md; with --docs also docs/mutants.md.

Usage: scripts/experiments/mutants.py [--backend gl,vulkan] [--only NAME[,NAME]] [--work DIR] [--out DIR] [--docs]
                                      [--replay-captures]
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import time

from mutant_table import MATRIX, MOMENTS, MUTANTS

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# --replay-captures' case: small, checked, captured when a check fails (RenderDoc on both APIs: its replay reads the
# frame back on either).
CAPTURED = ["--scene", "room", "--cube", "64", "--frame", "80x60", "--technique", "six_pass", "--filter", "hard",
            "--frames", "1", "--warmup", "0", "--benchmark_repetitions=1", "--images", "all", "--check"]
REPLAY = os.path.join(ROOT, "scripts", "replay_renderdoc.py")


def sh(cmd, cwd, log):
    with open(log, "a") as f:
        f.write(f"$ {' '.join(cmd)}\n")
        f.flush()
        return subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT).returncode


SELF_CHECK = "omnishadow self-check failed: "  # how a build-time check of the conventions refuses a build


def build(work, log):
    if sh(["cmake", "--preset", "release"], work, log):
        return False
    return sh(["cmake", "--build", "--preset", "release", "--target", "omnishadow", "-j2"], work, log) == 0


def build_mutant(work, log):
    """('built', ''), ('refused', the self-check's line) when one of the project's own build-time checks refused
    the mutant (caught before any run), or ('failed', '') when it did not compile (a broken mutant, not caught)."""
    start = os.path.getsize(log) if os.path.exists(log) else 0
    if build(work, log):
        return "built", ""
    with open(log, errors="replace") as f:
        f.seek(start)
        for line in f:
            if SELF_CHECK in line:
                return "refused", line.split(SELF_CHECK, 1)[1].strip()
    return "failed", ""


# The figure a check's row shows: the share of what it compared that was wrong.
HEADLINE = {"cube_texels": "bad_percent", "map_texels": "bad_percent", "max_error": "misclassified_percent"}


def failures(results_path):
    """{(case id, check): figures} of every finding that failed a case."""
    with open(results_path) as f:
        doc = json.load(f)
    return {(case["id"], finding["check"]): finding.get("figures", {})
            for case in doc["omnishadow"]["cases"] for finding in case.get("findings", [])
            if finding["status"] not in ("ok", "unsupported")}


def caught_by(found, baseline):
    """Per check, the cases it failed that the unmutated build passes, and the largest headline figure."""
    checks = {}
    for (case_id, check), figures in found.items():
        if (case_id, check) in baseline:
            continue  # fails without the mutant too (lavapipe's multiview): not evidence of catching it
        c = checks.setdefault(check, {"cases": 0, "figure": None, "example": case_id})
        c["cases"] += 1
        value = figures.get(HEADLINE.get(check, "percent_differing"))
        if value is not None:
            c["figure"] = max(c["figure"] or value, value)
    return checks


def listed(binary, key, env):
    """The values on `omnishadow list`'s `key:` line, comma-joined."""
    out = subprocess.run([binary, "list"], capture_output=True, text=True, env=env).stdout
    for line in out.splitlines():
        if line.startswith(key + ": "):
            return line[len(key) + 2:].replace(" ", "")
    sys.exit(f"mutants: `{binary} list` has no '{key}:' line")


def run_matrix(work, out, name, backend, log, extra=()):
    """Runs the matrix (plus `extra` arguments) with the clone's build; (exit code, failures)."""
    run_dir = os.path.join(out, name)
    shutil.rmtree(run_dir, ignore_errors=True)
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    binary = os.path.join(work, "build", "release", "omnishadow")
    if any(MOMENTS in a for a in extra):
        extra = [a.replace(MOMENTS, listed(binary, "moments filters", env)) for a in extra]
    matrix = list(MATRIX)
    if "--scene" in extra:  # a mutant's own scenes replace the default ones
        at = matrix.index("--scene")
        del matrix[at:at + 2]
    with open(log, "a") as f:
        code = subprocess.run([binary, "run", "--backend", backend, "--out", run_dir, *matrix, *extra], cwd=work,
                              env=env, stdout=f, stderr=subprocess.STDOUT).returncode
    results = os.path.join(run_dir, "results.json")
    return code, failures(results) if os.path.exists(results) else {}


def pixels(png):
    from PIL import Image
    return list(Image.open(png).convert("RGBA").getdata())


def lit_pixels(folder):
    """The lit image a run folder holds (its one case's), as RGBA pixels, or None."""
    found = sorted(glob.glob(os.path.join(folder, "images", "**", "lit.png"), recursive=True))
    return pixels(found[0]) if found else None


def run_case(work, run_dir, backend, log, *extra):
    shutil.rmtree(run_dir, ignore_errors=True)
    env = dict(os.environ, XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    with open(log, "a") as f:
        return subprocess.run([os.path.join(work, "build", "release", "omnishadow"), "run", "--backend", backend,
                               "--out", run_dir, *CAPTURED, *extra], cwd=work, env=env, stdout=f,
                              stderr=subprocess.STDOUT).returncode


def replay_capture(work, out, name, backend, log, clean):
    """Captures the mutant's failing case and replays it: {captured, reproduces, differing (from clean), ...}."""
    run_dir = os.path.join(out, f"{name}-capture-{backend}")
    code = run_case(work, run_dir, backend, log, "--capture", "failed", "--capture-tool", "renderdoc")
    listing = os.path.join(run_dir, "captures.json")
    listed = json.load(open(listing))["captures"] if os.path.exists(listing) else []
    got = {"exit_code": code, "captured": False, "reproduces": False, "differing": 0, "pixels": len(clean or [])}
    if not listed or listed[0]["status"] != "captured":
        got["reason"] = listed[0].get("reason", "") if listed else "the case passed its checks: nothing captured"
        return got
    rdc = os.path.join(run_dir, listed[0]["file"])
    png = rdc + ".replayed.png"
    env = dict(os.environ, EGL_PLATFORM="surfaceless", XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    with open(log, "a") as f:
        replayed = subprocess.run(["/usr/bin/python3", REPLAY, rdc, "--out", png], env=env, stdout=f,
                                  stderr=subprocess.STDOUT).returncode == 0
    mine = pixels(png) if replayed else None
    harness = lit_pixels(rdc[:-len(".rdc")] + ".run")  # the capture run's own folder, captures/<case>.run
    got.update(captured=True, reproduces=mine is not None and mine == harness,
               differing=sum(a != b for a, b in zip(mine or [], clean or [])))
    return got


def replay_lines(rows):
    """The report's section on captures: per mutant and API, whether the replayed capture shows the bug."""
    lines = ["\n## Captures of the mutants\n",
             f"Each mutant's build ran `omnishadow run {' '.join(CAPTURED)} --capture failed --capture-tool "
             "renderdoc`; the capture was replayed by scripts/replay_renderdoc.py. Replays the bug = the replayed "
             "image is the mutant's harness image bit for bit and differs from the unmutated build's.\n",
             "| mutant | API | captured | replay = mutant's image | pixels differing from unmutated | replays the bug |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        for b, g in r.get("replays", {}).items():
            lines.append(f"| `{r['name']}` | {b} | {'yes' if g['captured'] else 'no: ' + g.get('reason', '')} | "
                         f"{'yes' if g['reproduces'] else 'no'} | {g['differing']} of {g['pixels']} | "
                         f"{'yes' if replays_bug(g) else '**no**'} |")
    return lines


def replays_bug(g):
    return g["captured"] and g["reproduces"] and g["differing"] > 0


def headline(checks):
    """'cube_texels (24 cases, 30.2%)': the checks that failed most cases, each with its largest headline figure."""
    if not checks:
        return "-"
    items = sorted(checks.items(), key=lambda kv: -kv[1]["cases"])
    return "; ".join(f"{check} ({c['cases']} cases" + (f", {c['figure']:.3g}%" if c["figure"] is not None else "")
                     + ")" for check, c in items[:3])


def write_report(out, rows, backends, seconds, commit, docs):
    caught = sum(r["caught"] for r in rows)
    md = [f"# Mutation suite: {caught} of {len(rows)} mutants caught by the harness's checks\n",
          f"Generated by `scripts/experiments/mutants.py --docs` at commit {commit} ({seconds / 60:.0f} min). Each mutant is "
          "one change to the shadow pipeline, built in a scratch clone and run with `omnishadow run --backend "
          f"{backends} {' '.join(MATRIX)}` (the default scenes; no unit test, no committed baseline). The unmutated "
          "build runs the same matrix first: a check counts only for the cases it fails with the mutant and passes "
          "without (lavapipe's multiview cases fail either way). Caught = every API has such a case (and exits 1), "
          "or one of the project's build-time self-checks refused the mutant before any run; the checks column lists them with their largest figure (cube texels wrong, pixels misclassified, or "
          "values differing, in %).\n",
          "| mutant | change | caught | exit codes | failed checks (cases, largest figure) |", "|---|---|---|---|---|"]
    for r in rows:
        codes = ", ".join(f"{b} {v['exit_code']}" for b, v in r["runs"].items())
        checks = " / ".join(f"{b}: {headline(v['checks'])}" for b, v in r["runs"].items())
        if r["build"] != "built":  # never ran: refused by a build-time self-check, or did not compile
            codes = "build refused" if r["build"] == "refused" else "build failed"
            checks = f"self-check: {r['refused_by']}" if r["build"] == "refused" else "did not compile"
        md.append(f"| `{r['name']}` | {r['change']} | {'yes' if r['caught'] else '**no**'} | {codes} | {checks} |")
    if any(r.get("replays") for r in rows):
        md += replay_lines(rows)
    text = "\n".join(md) + "\n"
    with open(os.path.join(out, "mutants.md"), "w") as f:
        f.write(text)
    with open(os.path.join(out, "mutants.json"), "w") as f:
        json.dump({"commit": commit, "matrix": MATRIX, "rows": rows}, f, indent=2)
    if docs:
        with open(os.path.join(ROOT, "docs", "mutants.md"), "w") as f:
            f.write(text)
    print(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--backend", default="gl,vulkan")
    parser.add_argument("--only", help="comma list of mutant names")
    parser.add_argument("--work", default="/tmp/omnishadow-mutants", help="scratch clone (kept between runs)")
    parser.add_argument("--out", default=os.path.join(ROOT, "results", time.strftime("mutants-%Y%m%d-%H%M%S")))
    parser.add_argument("--docs", action="store_true", help="also write docs/mutants.md")
    parser.add_argument("--replay-captures", action="store_true",
                        help="capture each mutant's failing case with RenderDoc and replay it (needs renderdoccmd, "
                        "librenderdoc, python3-renderdoc, python3-pil)")
    args = parser.parse_args()
    mutants = [m for m in MUTANTS if not args.only or m[0] in args.only.split(",")]
    if not mutants:
        sys.exit(f"mutants: --only {args.only}: no such mutant; known: {', '.join(m[0] for m in MUTANTS)}")
    os.makedirs(args.out, exist_ok=True)
    log = os.path.join(args.out, "mutants.log")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    # A clone of this commit (kept, so its build directory makes later runs incremental).
    if not os.path.isdir(os.path.join(args.work, ".git")):
        subprocess.run(["git", "clone", "-q", ROOT, args.work], check=True)
    subprocess.run(["git", "fetch", "-q", ROOT, "HEAD"], cwd=args.work, check=True)
    subprocess.run(["git", "checkout", "-q", "--force", "FETCH_HEAD"], cwd=args.work, check=True)
    started = time.time()
    if not build(args.work, log):
        sys.exit(f"mutants: the unmutated build failed; see {log}")
    # The unmutated build's failures, per backend and per matrix the selected mutants run (before any mutation).
    baselines = {}
    for _, _, _, _, *rest in mutants:
        extra = tuple(rest[0]) if rest else ()
        for b in args.backend.split(","):
            if (b, extra) not in baselines:
                label = "unmutated-" + b + ("-" + "-".join(extra[1:]).replace(",", "_") if extra else "")
                baselines[(b, extra)] = run_matrix(args.work, args.out, label, b, log, extra)[1]
    clean = {}
    for b in args.backend.split(",") if args.replay_captures else []:
        run_dir = os.path.join(args.out, f"capture-unmutated-{b}")
        run_case(args.work, run_dir, b, log)
        clean[b] = lit_pixels(run_dir)
    rows = []
    for name, path, mutate, change, *rest in mutants:
        extra = rest[0] if rest else []
        target = os.path.join(args.work, path)
        with open(target) as f:
            original = f.read()
        try:
            with open(target, "w") as f:
                f.write(mutate(original))
            outcome, refusal = build_mutant(args.work, log)
            built = outcome == "built"
            runs = {}
            for b in args.backend.split(",") if built else []:
                base = baselines[(b, tuple(extra))]
                code, found = run_matrix(args.work, args.out, f"{name}-{b}", b, log, extra)
                runs[b] = {"exit_code": code, "checks": caught_by(found, base)}
            replays = {b: replay_capture(args.work, args.out, name, b, log, clean[b]) for b in clean if built}
        finally:
            with open(target, "w") as f:
                f.write(original)
        caught = outcome == "refused" or (built and all(r["exit_code"] == 1 and r["checks"] for r in runs.values()))
        rows.append({"name": name, "file": path, "change": change, "build": outcome, "built": built,
                     "caught": caught, "runs": runs})
        if refusal:
            rows[-1]["refused_by"] = refusal
        if clean and built:
            rows[-1]["replays"] = replays
        verdict = {"refused": "caught at build", "failed": "SURVIVED (did not compile: fix the mutant)"}
        print(f"{name}: {verdict.get(outcome, 'caught' if caught else 'SURVIVED')} "
              f"({time.time() - started:.0f}s)", flush=True)
    build(args.work, log)  # leave the clone unmutated and built
    write_report(args.out, rows, args.backend, time.time() - started, commit, args.docs)
    replayed = all(replays_bug(g) for r in rows for g in r.get("replays", {}).values())
    sys.exit(0 if replayed and all(r["caught"] for r in rows) else 1)


if __name__ == "__main__":
    main()
