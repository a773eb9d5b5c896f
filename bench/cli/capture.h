#pragma once
// `run --capture failed|crashed|all|none`: after the matrix, each selected case is run again, alone (its id
// as the run's --benchmark_filter, one repetition, no crash isolation), in a process of its own under the
// API's capture tool, so that a driver team can replay it without this harness. Vulkan: GFXReconstruct's
// capture layer (Debian's gfxreconstruct), replayed by `gfxrecon-replay`: OUT/captures/<case>.gfxr. GL:
// RenderDoc (Debian's renderdoccmd, librenderdoc): the capture run starts under `renderdoccmd capture` and
// brackets its check frame with RenderDoc's in-application API (bench/run/renderdoc_frames.h), since the
// harness never presents: OUT/captures/<case>.rdc, replayed headless by scripts/replay_renderdoc.py
// (RenderDoc's Python module). apitrace cannot serve GL: its EGL wrapper answers libepoxy's dlopen of
// libGL.so.1 with itself, which has no glXGetCurrentContext, and libepoxy aborts. Each capture run's folder
// (<case>.run) and output
// (<case>.log) lie beside its file ('/' in the id as '_'); OUT/captures.json and results.json's "captures"
// list every selected case with its tool, the tool's version, the file and its size, and the command that
// replays it, or why there is none. A capture past --capture-max-mb is stopped and not kept.
#include <string>
#include <vector>

namespace omnishadow::bench {

struct CaptureSettings {
  std::string mode = "none";  // failed, crashed, all, none
  std::string tool =
      "auto";  // --capture-tool: auto (Vulkan GFXReconstruct, GL RenderDoc), gfxreconstruct, renderdoc
  std::vector<std::string> args;  // the run's arguments after the program name ("run", then the options)
  std::string out_dir;            // the run's folder, holding its results.json
  double timeout_s = 300.0;       // a capture run that takes longer is killed and said
  double max_mb =
      1024.0;  // --capture-max-mb: a capture file that grows past it is cut (its run killed) and said
};

// Captures the selected cases of OUT/results.json and records them there; one line per case on stdout. A
// capture that fails is a line and an entry, never a lost result.
void capture_cases(const CaptureSettings& settings);

// The arguments of a capture run of case `id`: the run's own, less those that choose the folder, the cases,
// the repetitions, the isolation and the captures, then those of the capture; --backend narrowed to the
// case's API, so that the capture holds that API alone.
std::vector<std::string> capture_run_args(const std::vector<std::string>& args, const std::string& id,
                                          const std::string& out_dir);

// Whether the Vulkan loader finds GFXReconstruct's capture layer, given VK_LAYER_PATH and VK_ADD_LAYER_PATH
// (either may be null): a folder of the first, colon-separated, which replaces the system's folders, else one
// of the second's or of the system's.
bool gfxreconstruct_layer_in(const char* layer_path, const char* add_layer_path);

}  // namespace omnishadow::bench
