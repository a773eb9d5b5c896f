#!/usr/bin/python3
"""The fleet's workflow files parse and call the scripts the fleet play test runs (tests/fleet_play.sh)."""
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

    github = load(".github/workflows/gpu-fleet.yml")
    jobs = github["jobs"]
    matrix = jobs["bench"]["strategy"]["matrix"]
    assert len(matrix["shard"]) == int(jobs["bench"]["env"]["OMNISHADOW_SHARD_COUNT"]), "shard list = count"
    assert "matrix.shard" in jobs["bench"]["env"]["OMNISHADOW_SHARD_INDEX"]
    assert set(jobs["merge"]["strategy"]["matrix"]["device"]) == set(matrix["device"])
    assert "fleet_shard.sh" in scripts_of(jobs["bench"])
    assert "fleet_merge.sh" in scripts_of(jobs["merge"]) and "fleet_compare.sh" in scripts_of(jobs["merge"])
    for path in ("scripts/ci/fleet_shard.sh", "scripts/ci/fleet_merge.sh", "scripts/ci/fleet_compare.sh"):
        assert os.access(os.path.join(ROOT, path), os.X_OK), f"{path} is not executable"
    print("workflows: .gitlab-ci.yml and .github/workflows/gpu-fleet.yml parse and call the fleet scripts")


if __name__ == "__main__":
    try:
        main()
    except AssertionError as e:
        sys.exit(f"workflows_test: {e}")
