#!/usr/bin/env bash
# Fuzz the readers of untrusted files with libFuzzer (clang): the scene loader, the results reader that
# compare/merge use, and the OBJ and glTF loaders (tinyobjloader, tinygltf). Usage: scripts/fuzz.sh [seconds per target, default 600] [target ...]
# Builds fuzz/ with clang into build/fuzz, grows a corpus in build/fuzz/corpus/<target> from fuzz/seeds/ and the
# committed scenes, and writes build/fuzz/report.md (executions, time, findings). A finding is saved under
# build/fuzz/artifacts/<target>/; commit it to tests/fuzz_regressions/<target>/ once fixed (ctest replays those).
# `scripts/fuzz.sh --smoke` (CI): a fixed seed and a fixed number of runs per target, so the job is repeatable.
# Exit 0: no finding; 1: a finding; 2: could not build.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=()
if [ "${1:-}" = "--smoke" ]; then
  seconds=0
  limit=(-seed=1 -runs=20000)
  shift
else
  seconds=${1:-600}
  shift || true
  limit=(-max_total_time="$seconds")
fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene results obj gltf)
bash scripts/setup.sh --fuzz >/dev/null
clangxx=$(command -v clang++ || command -v clang++-14 || true)
[ -n "$clangxx" ] || { echo "fuzz.sh: clang++ not found (bash scripts/setup.sh --fuzz installs it)" >&2; exit 2; }

out=build/fuzz
CXX=$clangxx cmake -S fuzz -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null || exit 2
cmake --build "$out" -j2 >/dev/null || exit 2

report="$out/report.md"
{
  echo "# Fuzzing report"
  echo
  echo "$(date -u +%Y-%m-%dT%H:%M:%SZ), commit $(git rev-parse --short=12 HEAD 2>/dev/null || echo unknown), clang $($clangxx -dumpversion), ${limit[*]} per target"
  echo
  echo "| target | executions | seconds | exec/s | corpus | coverage (edges) | findings |"
  echo "|---|---|---|---|---|---|---|"
} > "$report"
status=0
for t in "${targets[@]}"; do
  corpus="$out/corpus/$t"; artifacts="$out/artifacts/$t"
  mkdir -p "$corpus" "$artifacts"
  seeds=()
  for d in "fuzz/seeds/$t" "tests/fuzz_regressions/$t"; do [ -d "$d" ] && seeds+=("$d"); done
  [ "$t" = scene ] && seeds+=(scenes)
  dict=fuzz/json.dict
  [ "$t" = obj ] && dict=fuzz/obj.dict
  # Seed folders hold non-inputs too (README.md, .obj files): libFuzzer only reads them, never writes there.
  log="$out/$t.log"
  set +e
  "$out/${t}_fuzzer" "${limit[@]}" -dict="$dict" -max_len=65536 -rss_limit_mb=4096 \
    -timeout=10 -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" "${seeds[@]}" > "$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  secs=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | awk '{print $5}' || true)
  [ -z "$secs" ] && secs=$seconds
  [ "$secs" -eq 0 ] && secs=1
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | awk '{print $2}')
  units=$(ls "$corpus" | wc -l)
  findings=$(ls "$artifacts" | wc -l)
  rate=$(( execs / (secs > 0 ? secs : 1) ))
  echo "| $t | $execs | $secs | $rate | $units | ${cov:-?} | $findings |" >> "$report"
  echo "$t: $execs executions in $secs s ($rate/s), corpus $units, cov ${cov:-?}, findings $findings (exit $rc)"
  if [ $rc -ne 0 ] || [ "$findings" -ne 0 ]; then
    status=1
    echo "  finding: see $log and $artifacts/" >&2
    grep -m3 -E 'contract violated|ERROR: |SUMMARY' "$log" >&2 || true
  fi
done
echo "report: $report"
exit $status
