#pragma once
// A run in the formats the dashboards teams already run read (`omnishadow export RUN --format F`): Bencher's
// Metric Format (BMF: {case: {measure: {value, lower_value, upper_value}}}) and github-action-benchmark's
// custom "smaller is better" list ([{name, unit, value, range, extra}]). Per timed case: the frame's wall,
// CPU and GPU time (the median of the repetitions' means, with their least and greatest), the misclassified
// pixels where the accuracy was measured, and whether the case is ok (1) or not (0), so that a dashboard
// alerts on statuses and accuracy as well as time.

#include <nlohmann/json.hpp>
#include <string>

#include "bench/io/results_reader.h"

namespace omnishadow::bench {

enum class ExportFormat { bencher, github_action_benchmark };
// "bencher" or "github-action-benchmark"; throws std::invalid_argument naming the valid ones.
ExportFormat parse_export_format(const std::string& name);
nlohmann::json export_run(const RunData& run, ExportFormat format);

}  // namespace omnishadow::bench
