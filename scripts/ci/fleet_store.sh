#!/usr/bin/env bash
# Stores a fleet's merged run into the results database (docs/store.md) when a CI variable names one:
# OMNISHADOW_STORE_URL, a PostgreSQL URL for a fleet (postgresql://USER:PASSWORD@HOST:PORT/DATABASE; sqlite:PATH
# works too). Only the default branch's runs, the commits that land, unless FLEET_STORE_ALL=1: a merge request's run
# answers its own question and would mix into the history. Without the variable: one line saying so, exit 0. A
# store that fails fails the job with the store's one line (its password never printed); the run stays in the job's
# artifacts. Runs before fleet_compare.sh, so that a run that regressed is stored too.
# Usage: scripts/ci/fleet_store.sh RUN
#   branch: CI_COMMIT_BRANCH (GitLab) or GITHUB_REF_NAME (GitHub); default: CI_DEFAULT_BRANCH, else
#   FLEET_DEFAULT_BRANCH, else main. A merge request (CI_MERGE_REQUEST_IID, GITHUB_BASE_REF) is never the default.
set -euo pipefail
run="${1:?usage: scripts/ci/fleet_store.sh RUN}"
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
if [ -z "${OMNISHADOW_STORE_URL:-}" ]; then
  echo "fleet_store: OMNISHADOW_STORE_URL is not set: the merged run is not stored (docs/store.md)"
  exit 0
fi
branch="${CI_COMMIT_BRANCH:-${GITHUB_REF_NAME:-}}"
default="${CI_DEFAULT_BRANCH:-${FLEET_DEFAULT_BRANCH:-main}}"
if [ -n "${CI_MERGE_REQUEST_IID:-}${GITHUB_BASE_REF:-}" ] || [ "$branch" != "$default" ]; then
  if [ "${FLEET_STORE_ALL:-}" != 1 ]; then
    echo "fleet_store: '${branch:-a merge request}' is not the default branch '$default': not stored (FLEET_STORE_ALL=1 stores every run)"
    exit 0
  fi
fi
"$bin" store "$run" --db "$OMNISHADOW_STORE_URL"
