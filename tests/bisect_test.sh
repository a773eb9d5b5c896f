#!/usr/bin/env bash
# scripts/ci/bisect.sh finds an injected regression: a toy repository of six commits whose "build" fails at one
# (skipped, exit 125) and whose "run" writes a real omnishadow run with its work counters scaled by work.txt; the
# fifth commit doubles the work. `omnishadow compare --no-timing` is the verdict, as in a real bisection.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${OMNISHADOW_BIN:-$here/build/release/omnishadow}"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
if reason="$("$bin" list | grep -m1 'gl: unavailable')"; then
  echo "bisect test skipped: OpenGL backend unavailable here: $reason"
  exit 77
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bin" run --backend gl --scene room --cube 32 --frame 64x48 --technique six_pass --filter hard --frames 1 \
  --warmup 0 --no-accuracy --images none --out "$tmp/fixture" >/dev/null 2>&1
toy="$tmp/toy"
mkdir -p "$toy" && cd "$toy"
git init -q && git config user.email t@example.com && git config user.name toy
echo 1 > work.txt
echo 'test ! -f broken' > build.sh
cat > run.sh <<PY
/usr/bin/python3 - "\$OUT" <<'INNER'
import json, os, shutil, sys
out = sys.argv[1]
shutil.copytree("$tmp/fixture", out)
work = int(open("work.txt").read())
path = os.path.join(out, "results.json")
doc = json.load(open(path))
for case in doc["omnishadow"]["cases"]:
    for name, value in case["counters"]["shadow"].items():
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            case["counters"]["shadow"][name] = value * work
json.dump(doc, open(path, "w"))
INNER
PY
commit() { git add -A && git commit -qm "$1" && git rev-parse HEAD; }
c0="$(commit 'good')"
echo '# comment' >> build.sh; commit 'a comment' >/dev/null
touch broken; commit 'breaks the build' >/dev/null
rm broken; commit 'fixes the build' >/dev/null
echo 2 > work.txt; c4="$(commit 'doubles the work')"
echo '# another' >> build.sh; c5="$(commit 'another comment')"
cd "$here"
bash scripts/ci/bisect.sh "$c0" "$c5" --repo "$toy" --work "$tmp/work" --build 'bash build.sh' --run 'bash run.sh' \
  -- --no-timing > "$tmp/bisect.out" 2>&1 || { cat "$tmp/bisect.out"; cat "$tmp/work/.bisect-runs/bisect.log" || true; exit 1; }
found="$(cat "$tmp/work/bisect.txt")"
[ "$found" = "$c4" ] || { echo "bisect found $found, expected $c4"; cat "$tmp/bisect.out"; exit 1; }
# git bisect visits the unbuildable third commit on this linear history (deterministic): it must be skipped.
grep -q "build failed: skip" "$tmp/work/.bisect-runs/bisect.log" || {
  echo "bisect never reported skipping the commit whose build fails"; cat "$tmp/work/.bisect-runs/bisect.log"; exit 1; }
echo "bisect test: found the injected regression $c4"
