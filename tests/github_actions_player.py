"""Plays a GitHub Actions reusable workflow's jobs on this machine, as far as the fleet's workflow needs: the jobs in
`needs` order, a matrix, `run:` steps under bash with the runner's environment files (GITHUB_ENV,
GITHUB_STEP_SUMMARY), actions/checkout, and actions/upload-artifact / download-artifact with their documented
semantics (an artifact's root is the least common ancestor of its paths; v4 keeps no file modes, so an executable
must travel in a tar; a `pattern` download puts each artifact in its own folder). Expressions are looked up, not
evaluated: one the player does not know fails the play, naming it, so a workflow change cannot pass unplayed.
Used by tests/fleet_pipeline_play.py."""
import json
import os
import shutil
import subprocess


class PlayError(AssertionError):
    pass


class Player:
    def __init__(self, workflow, repo, sha, event, work, base_ref="", secrets=None):
        self.workflow, self.repo, self.sha, self.event, self.work = workflow, repo, sha, event, work
        self.base_ref = base_ref
        self.secrets = secrets or {}  # a secret the repository lacks reads as "", as on GitHub
        self.artifacts = os.path.join(work, "artifacts")
        self.results = {}      # job id -> "success" | "failure" | "skipped"
        self.summaries = {}    # job id -> what its steps wrote to GITHUB_STEP_SUMMARY
        self.logs = {}         # job id -> the steps' output
        os.makedirs(self.artifacts, exist_ok=True)

    def value(self, expression, ctx):
        known = {
            "inputs.device": ctx["inputs"]["device"],
            "inputs.gpus": ctx["inputs"]["gpus"],
            "fromJSON(inputs.gpus)": json.loads(ctx["inputs"]["gpus"]),
            "matrix.gpu": ctx.get("matrix", {}).get("gpu"),
            "strategy.job-index": ctx.get("job_index"),
            "strategy.job-total": ctx.get("job_total"),
            "github.workspace": ctx.get("workspace"),
            "github.base_ref || 'main'": self.base_ref or "main",
            "github.event.repository.default_branch": "main",
            "secrets.OMNISHADOW_STORE_URL": self.secrets.get("OMNISHADOW_STORE_URL", ""),
            "!cancelled()": True,
            "!cancelled() && needs.build.result == 'success'": self.results.get("build") == "success",
        }
        if expression not in known:
            raise PlayError(f"the GitHub play does not know the expression '{expression}' (tests/github_actions_player.py)")
        return known[expression]

    def expand(self, text, ctx):
        if not isinstance(text, str):
            return text
        whole = text.strip()
        if whole.startswith("${{") and whole.endswith("}}") and whole.count("${{") == 1:
            return self.value(whole[3:-2].strip(), ctx)
        out, rest = "", text
        while "${{" in rest:
            head, tail = rest.split("${{", 1)
            expression, rest = tail.split("}}", 1)
            out += head + str(self.value(expression.strip(), ctx))
        return out + rest

    def condition(self, text, ctx, default):
        if text is None:
            return default
        text = text.strip()
        if not text.startswith("${{"):
            text = "${{ " + text + " }}"
        return bool(self.expand(text, ctx))

    def play(self, inputs):
        jobs = self.workflow["jobs"]
        for job_id in self.order(jobs):
            job = jobs[job_id]
            needs = job.get("needs", [])
            needs = [needs] if isinstance(needs, str) else needs
            ctx = {"inputs": inputs}
            default = all(self.results.get(n) == "success" for n in needs)
            if not self.condition(job.get("if"), ctx, default):
                self.results[job_id] = "skipped"
                continue
            matrix = job.get("strategy", {}).get("matrix")
            if matrix:
                (axis, values), = matrix.items()
                values = self.expand(values, ctx)
                outcomes = [self.run_job(job_id, f"{job_id}-{i}", job, dict(ctx, matrix={axis: v}, job_index=i,
                                                                           job_total=len(values)))
                            for i, v in enumerate(values)]
            else:
                outcomes = [self.run_job(job_id, job_id, job, ctx)]
            self.results[job_id] = "success" if all(outcomes) else "failure"
        return self.results

    @staticmethod
    def order(jobs):
        done, order = set(), []
        while len(order) < len(jobs):
            ready = [j for j in jobs if j not in done and all(n in done for n in (
                [jobs[j]["needs"]] if isinstance(jobs[j].get("needs"), str) else jobs[j].get("needs", [])))]
            if not ready:
                raise PlayError("the workflow's needs form a cycle")
            for j in ready:
                done.add(j)
                order.append(j)
        return order

    def run_job(self, job_id, name, job, ctx):
        workspace = os.path.join(self.work, "jobs", name)
        ctx = dict(ctx, workspace=workspace)
        files = os.path.join(self.work, "files", name)
        os.makedirs(files, exist_ok=True)
        env_file, summary_file = os.path.join(files, "env"), os.path.join(files, "summary.md")
        open(env_file, "w").close()
        open(summary_file, "w").close()
        env = dict(os.environ, HOME=os.path.join(self.work, "home"), GITHUB_WORKSPACE=workspace,
                   GITHUB_ENV=env_file, GITHUB_STEP_SUMMARY=summary_file, GITHUB_EVENT_NAME=self.event,
                   GITHUB_BASE_REF=self.base_ref, GITHUB_SHA=self.sha, CI="true", GITHUB_ACTIONS="true")
        os.makedirs(env["HOME"], exist_ok=True)
        for scope in (self.workflow.get("env", {}), job.get("env", {})):
            if not isinstance(scope, dict):
                raise PlayError(f"job {job_id}: env is {scope!r}, not a mapping (GitHub rejects the workflow)")
            env.update({k: str(self.expand(v, ctx)) for k, v in scope.items()})
        ok, log = True, []
        for step in job["steps"]:
            if not self.condition(step.get("if"), ctx, ok):
                continue
            step_env = dict(env, **{k: str(self.expand(v, ctx)) for k, v in step.get("env", {}).items()})
            try:
                if "uses" in step:
                    self.action(step, ctx, workspace)
                elif job.get("container") and step["run"].startswith("apt-get"):
                    log.append(f"(container set-up skipped: this machine is the {job['container']} it installs into)")
                else:
                    r = subprocess.run(["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c",
                                        self.expand(step["run"], ctx)], cwd=workspace, env=step_env,
                                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
                    log.append(f"$ {step['run']}\n{r.stdout}")
                    if r.returncode:
                        log.append(f"(exit {r.returncode})")
                        ok = False
            except (OSError, subprocess.SubprocessError, KeyError) as e:
                log.append(f"(step failed: {e})")
                ok = False
            with open(env_file) as f:
                env.update(line.rstrip("\n").split("=", 1) for line in f if "=" in line)
        with open(summary_file) as f:
            self.summaries[name] = f.read()
        self.logs[name] = "\n".join(log)
        return ok

    def action(self, step, ctx, workspace):
        uses, args = step["uses"], {k: self.expand(v, ctx) for k, v in step.get("with", {}).items()}
        if uses.startswith("actions/checkout@"):
            subprocess.run(["git", "clone", "-q", self.repo, workspace], check=True)
            subprocess.run(["git", "-C", workspace, "checkout", "-q", self.sha], check=True)
        elif uses.startswith("actions/upload-artifact@"):
            paths = [os.path.join(workspace, p.strip()) for p in args["path"].splitlines() if p.strip()]
            root = os.path.commonpath(paths) if len(paths) > 1 else paths[0].rstrip("/")
            if os.path.isfile(root):
                root = os.path.dirname(root)
            dest = os.path.join(self.artifacts, args["name"])
            for p in paths:
                copy_without_modes(p.rstrip("/"), os.path.join(dest, os.path.relpath(p.rstrip("/"), root)))
        elif uses.startswith("actions/download-artifact@"):
            into = os.path.join(workspace, args.get("path", "."))
            if "name" in args:
                copy_without_modes(os.path.join(self.artifacts, args["name"]), into)
            else:
                prefix = args["pattern"].rstrip("*")
                for name in sorted(os.listdir(self.artifacts)):
                    if name.startswith(prefix):
                        copy_without_modes(os.path.join(self.artifacts, name), os.path.join(into, name))
        else:
            raise PlayError(f"the GitHub play does not know the action '{uses}'")


def copy_without_modes(src, dst):
    """An artifact round trip: contents kept, file modes not (actions/upload-artifact v4)."""
    if os.path.isfile(src):
        os.makedirs(os.path.dirname(dst) or ".", exist_ok=True)
        shutil.copyfile(src, dst)
        return
    for dirpath, _, names in os.walk(src):
        for n in names:
            s = os.path.join(dirpath, n)
            copy_without_modes(s, os.path.join(dst, os.path.relpath(s, src)))
