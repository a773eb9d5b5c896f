#!/usr/bin/env bash
# The capture step: a failed case captured on the GPU and replayed there. Sourced by scripts/gpu_acceptance.sh.

# A case captured on the GPU and replayed there: room made to fail on purpose (--max-error 0.001) with --capture
# failed, both APIs. PASS when the Vulkan case's capture is written and gfxrecon-replay replays it on this driver
# (exit 0), and the GL case's RenderDoc capture, where there is one, replays too (scripts/replay_renderdoc.py;
# said, not judged, where RenderDoc's Python module is missing). Needs GFXReconstruct (and RenderDoc for GL) from
# Debian; on a machine without a package registry carry their .debs beside the others (device.sh unpacks them
# under /opt/carried).
step_capture() {
  note "## capture"
  # Carried packages (device.sh unpacks them under /opt/carried and points VK_LAYER_PATH at their layer folder,
  # where GFXReconstruct's manifest lies): the tools on PATH. renderdoccmd finds librenderdoc through its own
  # RPATH ($ORIGIN/../lib) and injects it into the capture run, whose in-application API finds it loaded.
  [ -d /opt/carried/usr/bin ] && export PATH="/opt/carried/usr/bin:$PATH"
  "$bin" run --backend gl,vulkan --scene room --cube 256 --technique six_pass --filter hard --frames 2 --warmup 0 \
    --images all --benchmark_repetitions=1 --max-error 0.001 --capture failed --out "$out/capture/run" \
    >"$out/capture/run.log" 2>&1
  note "- run --capture failed: exit $? (every case fails --max-error 0.001 on purpose, a quality verdict)"
  local listed file
  listed=$(/usr/bin/python3 - "$out/capture/run" <<'PY' 2>&1
import json, sys
captures = json.load(open(sys.argv[1] + "/captures.json"))["captures"]
for c in captures:
    print(f"  - {c['case']}: {c['status']}: {c.get('file', c.get('reason', ''))[:240]}")
    if c["case"].startswith("vulkan/") and c["status"] == "captured":
        print("FILE " + sys.argv[1] + "/" + c["file"])
    if c["case"].startswith("gl/") and c["status"] == "captured":
        print("GLFILE " + sys.argv[1] + "/" + c["file"])
PY
)
  grep -v -e '^FILE ' -e '^GLFILE ' <<<"$listed" | tee -a "$summary"
  file=$(sed -n 's/^FILE //p' <<<"$listed")
  local gl_file
  gl_file=$(sed -n 's/^GLFILE //p' <<<"$listed")
  if [ -n "$gl_file" ]; then
    if /usr/bin/python3 -c 'import renderdoc' 2>/dev/null; then
      EGL_PLATFORM="${EGL_PLATFORM:-surfaceless}" timeout 300 /usr/bin/python3 "$here/scripts/replay_renderdoc.py" \
        "$gl_file" --out "$out/capture/gl-replayed.png" >"$out/capture/gl-replay.log" 2>&1
      exit_note $? "GL capture replayed by RenderDoc (scripts/replay_renderdoc.py, $out/capture/gl-replayed.png)"
      # The replay holds to the capture run's own lit image (GL's invariance rule: same commands, same driver).
      /usr/bin/python3 - "$out/capture/gl-replayed.png" "${gl_file%.rdc}.run" <<'PY' 2>&1 | tee -a "$summary"
import glob, sys
from PIL import Image
lit = sorted(glob.glob(sys.argv[2] + "/images/**/lit.png", recursive=True))
a = list(Image.open(sys.argv[1]).convert("RGBA").getdata()) if lit else []
b = list(Image.open(lit[0]).convert("RGBA").getdata()) if lit else []
same = sum(x == y for x, y in zip(a, b))
print(f"- {'PASS' if b and same == len(a) == len(b) else 'FAIL'}: the GL replay equals the harness's lit image in "
      f"{same} of {len(b)} pixels")
PY
      grep -q 'FAIL: the GL replay' "$summary" && failed=1
    else
      note "- GL capture written, not replayed here: RenderDoc's Python module is missing (python3-renderdoc)"
    fi
  fi
  if [ -z "$file" ]; then
    note "- FAIL: no Vulkan capture (see $out/capture/run.log)"; failed=1; return
  fi
  timeout 300 gfxrecon-replay "$file" >"$out/capture/replay.log" 2>&1
  local code=$?
  [ "$code" -eq 0 ] && note "- PASS: gfxrecon-replay replayed $(basename "$file") ($(stat -c %s "$file") bytes)" ||
    { note "- FAIL: gfxrecon-replay exit $code (see $out/capture/replay.log)"; failed=1; }
  # Both traces as benchmarks on this driver (RenderDoc's GPU duration counter where the driver has it).
  local traces=("$file")
  [ -z "$gl_file" ] || ! /usr/bin/python3 -c 'import renderdoc' 2>/dev/null || traces+=("$gl_file")
  EGL_PLATFORM="${EGL_PLATFORM:-surfaceless}" timeout 240 /usr/bin/python3 "$here/scripts/replay_trace.py" \
    "${traces[@]}" --rounds 3 --out "$out/capture/replay.json" 2>&1 | sed 's/^/  - /' | tee -a "$summary"
  exit_note "${PIPESTATUS[0]}" "scripts/replay_trace.py on the captures ($out/capture/replay.json)"
}
