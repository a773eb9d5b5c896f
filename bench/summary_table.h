#pragma once
// The human summary of a run (summary.md and the end of stdout): statuses, technique ratios to six_pass for
// the shadow pass, filter ratios to hard for the lighting pass. Ratios come from one run on one machine,
// which is the only comparison a noisy or software-rendered machine supports.

#include <string>
#include <vector>

#include "bench/case_runner.h"

namespace omnishadow::bench {

std::string summary_markdown(const std::vector<CaseResult>& results);

}  // namespace omnishadow::bench
