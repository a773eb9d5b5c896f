# Sourced by CI entry points: `stage NAME COMMAND...` runs one stage, prints its time as it ends, and an EXIT trap
# prints every stage's time and status as a table, whether the entry point ends passing or failing. A failing stage
# ends the entry point with its exit code (set -e semantics), after the table.
stage_rows=()
stage() {
  local name="$1"; shift
  local start rc=0
  start=$(date +%s)
  echo "== stage $name: $*"
  "$@" || rc=$?
  local took=$(( $(date +%s) - start ))
  stage_rows+=("$name|$took|$rc")
  echo "== stage $name: exit $rc after ${took} s"
  return "$rc"
}
stage_table() {
  local total=0 row name took rc
  echo
  echo "| stage | seconds | exit |"
  echo "|---|---|---|"
  for row in "${stage_rows[@]}"; do
    IFS='|' read -r name took rc <<<"$row"
    total=$(( total + took ))
    echo "| $name | $took | $rc |"
  done
  echo "| total | $total | |"
}
trap stage_table EXIT
