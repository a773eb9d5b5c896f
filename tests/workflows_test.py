#!/usr/bin/python3
"""The fleet's workflow files parse, call the scripts the fleet play test runs (tests/fleet_play.sh), and hold what
the engines' documented semantics need: GitLab merge-request pipelines (so the note can be posted), artifact paths
without variables (expose_as) that keep the shards the merged run's images point into, no fork pull request on
GitHub's self-hosted GPU runners, no merge after a cancel, and one shard count per engine."""
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
    bench = [k for k in gitlab if k.startswith("bench:")]
    merge = [k for k in gitlab if k.startswith("merge:")]
    assert bench and len(bench) == len(merge), "one bench and one merge job per device"
    assert gitlab[".bench"]["parallel"] >= 2, "shards in parallel"
    assert "fleet_shard.sh" in scripts_of(gitlab[".bench"])
    assert "fleet_merge.sh" in scripts_of(gitlab[".merge"]) and "fleet_compare.sh" in scripts_of(gitlab[".merge"])
    for job in merge:
        device = gitlab[job]["variables"]["DEVICE"]
        assert gitlab[job]["needs"] == [f"bench:{device}"], job
    rules = [r.get("if", "") for r in gitlab["workflow"]["rules"]]
    assert any('$CI_PIPELINE_SOURCE == "merge_request_event"' in r for r in rules), "merge-request pipelines"
    artifacts = gitlab[".merge"]["artifacts"]
    assert "expose_as" in artifacts and not any("$" in p for p in artifacts["paths"]), "expose_as needs fixed paths"
    merge_script = scripts_of(gitlab[".merge"])
    assert "fleet/shards" in merge_script and artifacts["paths"] == ["fleet/"], "shards kept beside the merged run"
    assert "SHARDS" not in gitlab.get("variables", {}), "the shard count is parallel: alone"

    github = load(".github/workflows/gpu-fleet.yml")
    jobs = github["jobs"]
    matrix = jobs["bench"]["strategy"]["matrix"]
    assert len(matrix["shard"]) == int(jobs["bench"]["env"]["OMNISHADOW_SHARD_COUNT"]), "shard list = count"
    assert "matrix.shard" in jobs["bench"]["env"]["OMNISHADOW_SHARD_INDEX"]
    assert set(jobs["merge"]["strategy"]["matrix"]["device"]) == set(matrix["device"])
    assert "fleet_shard.sh" in scripts_of(jobs["bench"])
    assert "fleet_merge.sh" in scripts_of(jobs["merge"]) and "fleet_compare.sh" in scripts_of(jobs["merge"])
    same_repo = "github.event.pull_request.head.repo.full_name == github.repository"
    assert same_repo in jobs["bench"]["if"] and same_repo in jobs["merge"]["if"], "no fork PR on self-hosted runners"
    assert "!cancelled()" in jobs["merge"]["if"] and "always()" not in jobs["merge"]["if"], "no merge after a cancel"
    upload = [s for s in jobs["merge"]["steps"] if s.get("uses", "").startswith("actions/upload-artifact")][0]
    assert "shards/" in upload["with"]["path"] and "merged/" in upload["with"]["path"], "images uploaded with the run"
    assert "SHARDS" not in github.get("env", {}), "the shard count is the matrix's list alone"
    with open(os.path.join(ROOT, "scripts", "setup.sh")) as f:
        assert "curl" in f.read(), "setup.sh installs curl for the merge-request note"
    for path in ("scripts/ci/fleet_shard.sh", "scripts/ci/fleet_merge.sh", "scripts/ci/fleet_compare.sh"):
        assert os.access(os.path.join(ROOT, path), os.X_OK), f"{path} is not executable"
    print("workflows: .gitlab-ci.yml and .github/workflows/gpu-fleet.yml parse and call the fleet scripts")


if __name__ == "__main__":
    try:
        main()
    except AssertionError as e:
        sys.exit(f"workflows_test: {e}")
