#pragma once
// The summary's many-light table: for a run with several light counts, what each light costs and what the
// checked lights' error is as the number of lights grows, per layout, technique (its grouping of the shadow
// passes) and filter.

#include <sstream>
#include <vector>

#include "bench/run/case_result.h"

namespace omnishadow::bench {

// Appends "## Many lights: ..." to `md` when the results hold more than one light count; nothing otherwise.
void light_count_table(std::ostringstream& md, const std::vector<CaseResult>& results);

}  // namespace omnishadow::bench
