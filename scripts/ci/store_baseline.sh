#!/usr/bin/env bash
# Copies what `omnishadow compare` reads from a run into a baseline folder: results.json, summary.md and the images
# (lit, shadow factor, cube faces; a merged run's images may sit in its shards, as results.json points). DEST is
# replaced. Usage: scripts/ci/store_baseline.sh RUN DEST   (used by refresh_baselines.sh and fleet_baseline.sh)
set -euo pipefail
run="$(cd "$1" && pwd)"; dest="$2"
[ -f "$run/results.json" ] || { echo "store_baseline: $run holds no results.json" >&2; exit 2; }
rm -rf "$dest"
mkdir -p "$dest"
dest="$(cd "$dest" && pwd)"
cp "$run/results.json" "$dest/"
[ -f "$run/summary.md" ] && cp "$run/summary.md" "$dest/"
# Every image results.json names, at the same relative path (a merged run names ../shards/<i>/images/...: those
# are copied into the baseline's own images/ and results.json is rewritten to point there).
/usr/bin/python3 - "$run" "$dest" <<'PY'
import json, os, shutil, sys
run, dest = sys.argv[1], sys.argv[2]
wanted = ("lit.png", "shadow_factor.pfm", "cube_faces.png")
with open(os.path.join(run, "results.json")) as f:
    doc = json.load(f)
def visit(node):
    if isinstance(node, dict):
        return {k: visit(v) for k, v in node.items()}
    if isinstance(node, list):
        return [visit(v) for v in node]
    if isinstance(node, str) and node.endswith(wanted) and os.path.isfile(os.path.join(run, node)):
        rel = os.path.normpath(node)
        if rel.startswith(".."):  # a merged run's shard image: keep it inside the baseline
            rel = os.path.join("images", *[p for p in rel.split(os.sep) if p not in ("..", "images")])
        os.makedirs(os.path.dirname(os.path.join(dest, rel)), exist_ok=True)
        shutil.copyfile(os.path.join(run, node), os.path.join(dest, rel))
        return rel
    return node
doc = visit(doc)
tmp = os.path.join(dest, "results.json.tmp")
with open(tmp, "w") as f:
    json.dump(doc, f, indent=1)
os.replace(tmp, os.path.join(dest, "results.json"))
PY
echo "baseline: $dest ($(du -sh "$dest" | cut -f1))"
