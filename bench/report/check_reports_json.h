#pragma once
// The part of a case's results.json entry (bench/report/results_writer.h) that says what its checks found:
// each image check, the accuracy against exact visibility (pooled, and per light for many lights), and the
// checks' own reports (moments, texels against exact distances, lookups replayed, clustered lists, the update
// budget's staleness).

#include <nlohmann/json.hpp>
#include <vector>

#include "bench/run/case_result.h"

namespace omnishadow::bench {

nlohmann::json checks_to_json(const std::vector<CheckResult>& checks);
nlohmann::json accuracy_to_json(const Accuracy& a);
// A many-light case's checked lights, each against its own truth (its "accuracy" entry's "per_light").
nlohmann::json per_light_to_json(const CaseResult& r);
// Adds the checks' own reports that the case has to its entry `j`.
void add_check_reports(nlohmann::json& j, const CaseResult& r);

}  // namespace omnishadow::bench
