#!/usr/bin/python3
"""The fleet's workflow files parse, call the scripts the plays run (tests/fleet_play.sh, tests/fleet_pipeline_play.py),
and hold what the engines' documented semantics need: GitLab merge-request pipelines (so the note can be posted),
artifact paths without variables (expose_as) that keep the shards the merged run's images point into, no fork pull
request on GitHub's self-hosted GPU runners, no merge after a cancel, one build per device passed to its jobs, one
shard per GPU pinned to that GPU's runner and serialised on it, a fan-in per device that waits for that device only,
and one shard count per engine."""
import os
import sys

try:
    import yaml
except ImportError:  # a machine without Debian's package: say which, and skip (ctest SKIP_RETURN_CODE 77)
    print("SKIP: needs python3-yaml (Debian package; scripts/setup.sh installs it)")
    sys.exit(77)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load(path):
    with open(os.path.join(ROOT, path)) as f:
        return yaml.safe_load(f)


def scripts_of(job):
    steps = job.get("script") or [s.get("run", "") for s in job.get("steps", [])]
    flat = []
    for s in steps:
        flat += s if isinstance(s, list) else [s]
    return " ".join(flat)


def main():
    gitlab = load(".gitlab-ci.yml")
    devices = [k.split(":", 1)[1] for k in gitlab if k.startswith("bench:")]
    assert devices, "bench jobs per device"
    assert "fleet_build.sh" in scripts_of(gitlab[".build"]) and "fleet-build/" in gitlab[".build"]["artifacts"]["paths"]
    assert "fleet-build/bin/omnishadow" in gitlab["variables"]["OMNISHADOW_BIN"], "later jobs use the build artifact"
    assert "fleet_shard.sh" in scripts_of(gitlab[".bench"]) and "build.sh" not in scripts_of(gitlab[".bench"])
    assert "fleet_merge.sh" in scripts_of(gitlab[".merge"]) and "fleet_compare.sh" in scripts_of(gitlab[".merge"])
    merge = scripts_of(gitlab[".merge"])
    assert merge.index("fleet_store.sh") < merge.index("fleet_compare.sh"), "a regressed run is stored too"
    assert "build.sh" not in scripts_of(gitlab[".merge"]), "the fan-in uses the device's build, not its own"
    for device in devices:
        build, bench, merge = (gitlab[f"{kind}:{device}"] for kind in ("build", "bench", "merge"))
        assert device in build["tags"], f"build:{device} runs on that device's runners"
        (gpus,) = bench["parallel"]["matrix"]
        assert list(gpus) == ["GPU"] and len(gpus["GPU"]) >= 1, f"bench:{device}: one shard per GPU"
        assert f"{device}-gpu$GPU" in bench["tags"], f"bench:{device}: each shard pinned to its GPU's runner"
        assert bench["resource_group"] == f"{device}-gpu$GPU", f"bench:{device}: serialised per GPU across pipelines"
        assert bench["needs"] == [f"build:{device}"], f"bench:{device} waits for its own build only"
        assert merge["needs"] == [f"build:{device}", f"bench:{device}"], f"merge:{device} waits for its device only"
    rules = [r.get("if", "") for r in gitlab["workflow"]["rules"]]
    assert any('$CI_PIPELINE_SOURCE == "merge_request_event"' in r for r in rules), "merge-request pipelines"
    artifacts = gitlab[".merge"]["artifacts"]
    assert "expose_as" in artifacts and not any("$" in p for p in artifacts["paths"]), "expose_as needs fixed paths"
    merge_script = scripts_of(gitlab[".merge"])
    assert "fleet/shards" in merge_script and artifacts["paths"] == ["fleet/"], "shards kept beside the merged run"
    assert gitlab[".bench"]["artifacts"]["expire_in"] == artifacts["expire_in"], "shards live as long as the merged run"
    assert "SHARDS" not in gitlab.get("variables", {}), "the shard count is the GPU list alone"

    caller = load(".github/workflows/gpu-fleet.yml")
    same_repo = "github.event.pull_request.head.repo.full_name == github.repository"
    assert "pull_request_target" not in caller[True], "never run a fork's code with this repository's secrets"
    for name, job in caller["jobs"].items():
        assert job["uses"] == "./.github/workflows/fleet-device.yml", f"{name}: one call per device key"
        assert same_repo in job["if"], f"{name}: no fork pull request on self-hosted runners"
        assert job["with"]["device"] == name
    device = load(".github/workflows/fleet-device.yml")
    jobs = device["jobs"]
    assert "workflow_call" in device[True]
    assert jobs["bench"]["needs"] == "build" and jobs["merge"]["needs"] == ["build", "bench"]
    assert "fleet_build.sh" in scripts_of(jobs["build"]) and "tar -cf" in scripts_of(jobs["build"]), \
        "the build travels as a tar (upload-artifact v4 drops the executable bit)"
    assert "inputs.device" in " ".join(jobs["build"]["runs-on"])
    assert "matrix.gpu" in " ".join(jobs["bench"]["runs-on"]), "each shard pinned to its GPU's runner"
    assert "strategy.job-total" in str(jobs["bench"]["env"]["OMNISHADOW_SHARD_COUNT"]), "shard count = the GPU list's length"
    assert "strategy.job-index" in str(jobs["bench"]["env"]["OMNISHADOW_SHARD_INDEX"])
    assert "concurrency" not in jobs["bench"], "concurrency: cancels pending measurements"
    assert "fleet_shard.sh" in scripts_of(jobs["bench"]) and "build.sh" not in scripts_of(jobs["bench"])
    assert "fleet_merge.sh" in scripts_of(jobs["merge"]) and "fleet_compare.sh" in scripts_of(jobs["merge"])
    merge = scripts_of(jobs["merge"])
    assert merge.index("fleet_store.sh") < merge.index("fleet_compare.sh"), "a regressed run is stored too"
    assert "!cancelled()" in jobs["merge"]["if"] and "always()" not in jobs["merge"]["if"], "no merge after a cancel"
    upload = [s for s in jobs["merge"]["steps"] if s.get("uses", "").startswith("actions/upload-artifact")][0]
    assert "shards/" in upload["with"]["path"] and "merged/" in upload["with"]["path"], "images uploaded with the run"
    with open(os.path.join(ROOT, "scripts", "setup.sh")) as f:
        assert "curl" in f.read(), "setup.sh installs curl for the merge-request note"
    for path in ("scripts/ci/fleet_build.sh", "scripts/ci/fleet_shard.sh", "scripts/ci/fleet_merge.sh",
                 "scripts/ci/fleet_store.sh",
                 "scripts/ci/fleet_compare.sh", "scripts/ci/fleet_baseline.sh", "scripts/ci/store_baseline.sh"):
        assert os.access(os.path.join(ROOT, path), os.X_OK), f"{path} is not executable"
    print("workflows: .gitlab-ci.yml and the GitHub fleet workflows parse and hold one build, one shard per GPU and "
          "one fan-in per device")


if __name__ == "__main__":
    try:
        main()
    except AssertionError as e:
        sys.exit(f"workflows_test: {e}")
