#!/usr/bin/env bash
# Installs everything omnishadow needs from Debian 12's packages. Idempotent: installs only what is missing.
# --fuzz adds clang and its runtime (libFuzzer) for scripts/fuzz.sh.
set -euo pipefail

packages=(
  cmake g++ make pkg-config git
  libepoxy-dev libegl-dev libgl-dev libglm-dev nlohmann-json3-dev libcli11-dev libstb-dev
  libtinyobjloader-dev libtinygltf-dev     # OBJ and glTF 2.0 models (scenes/obj_loader.cpp, gltf_loader.cpp)
  assimp-testmodels                        # tests/gltf_loader_test.cpp, model_scene_test.cpp: third-party glTF 2.0 models
  glmark2-data                             # scenes/bunny.json (the default matrix): the Stanford bunny, bunny.obj
  libbenchmark-dev libbenchmark-tools libgtest-dev
  libegl-mesa0 libgl1-mesa-dri            # Mesa: llvmpipe through EGL surfaceless on machines without a GPU
  libvulkan-dev glslc mesa-vulkan-drivers vulkan-validationlayers  # Vulkan loader, SPIR-V compiler, lavapipe
  libmeshoptimizer-dev                     # mesh_shader's meshlets (backends/common/meshlets.cpp)
  libsoci-dev libpq-dev libsqlite3-dev    # the results store: SOCI with its SQLite and PostgreSQL backends
  libssl-dev                               # the results store: SHA-256 of each run's images (OpenSSL's libcrypto)
  postgresql                               # tests/store_test.py: a PostgreSQL server started in a temporary folder
  glslang-tools                            # tests: the GL-only shader variants (NV extensions) compile with glslang
  gfxreconstruct                           # run --capture: Vulkan captures (GFXReconstruct's layer, gfxrecon-replay)
  renderdoccmd librenderdoc librenderdoc-dev python3-renderdoc  # run --capture: GL captures (RenderDoc), replayed headless
  python3-pil                              # tests/capture_replay_test.py: the replayed image against the harness's
  python3 python3-scipy python3-matplotlib # scripts/ (compare.py, plots)
  python3-yaml                             # tests/workflows_test.py: the fleet workflow files parse
  chromium                                 # tests/report_test.sh: the HTML report rendered in a real browser
  valgrind                                 # callgrind: deterministic instruction counts (scripts/ci/instruction_counts.sh)
  curl                                     # scripts/ci/fleet_compare.sh posts the GitLab merge-request note
  ccache                                   # every build (CMakeLists.txt), the fleet plays' four builds share compilations
  clang-format                             # tests/format_test.sh: the tree as clang-format 14 writes it
  rsync                                    # gitlab-ci-local (tests/fleet_pipeline_play.py) copies the work tree with it
)
[ "${1:-}" = "--fuzz" ] && packages+=(clang-14 libclang-rt-14-dev)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "setup: installing ${missing[*]}"
$sudo apt-get update -q
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
