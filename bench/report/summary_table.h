#pragma once
// The human summary of a run (summary.md and the end of stdout): statuses, technique ratios to six_pass for
// the shadow pass, filter ratios to hard for the lighting pass. Ratios come from one run on one machine,
// which is the only comparison a noisy or software-rendered machine supports.

#include <string>
#include <vector>

#include "bench/run/case_result.h"
#include "bench/run/repetition_policy.h"
#include "bench/run/run_options.h"

namespace omnishadow::bench {

// Wall seconds of a run's two parts: the untimed part (check frames, read-backs, checks, the reference, image
// files) and the timed part (warm-up and timed frames of every repetition). Negative: not reached.
// One scene's loading, before the untimed part: a model's parse and bake is the user's own figure to know.
struct SceneLoad {
  std::string name;    // as in case ids
  std::string source;  // the file
  uint64_t triangles = 0;
  double seconds = 0.0;
};

struct RunPhases {
  double untimed_seconds = -1.0;
  double timed_seconds = -1.0;
  std::vector<SceneLoad> scene_loads;  // in --scene order
};

// `incomplete`: why the run is not whole ("stopped by SIGINT during ..."), said first; "" for a whole run.
std::string summary_markdown(const std::vector<CaseResult>& results, const RunPhases& phases = {},
                             const RepetitionPolicy& policy = {}, const std::string& incomplete = "");

}  // namespace omnishadow::bench
