#include "bench/report/light_count_table.h"

#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "bench/io/statistics.h"

namespace omnishadow::bench {
namespace {

// What a row holds fixed: everything but the light count.
std::string row_key(const CaseConfig& c) {
  CaseConfig one = c;
  one.light_count = 1;
  return one.id();
}

double median_of(const std::vector<FrameTiming>& frames, double (*get)(const FrameTiming&)) {
  std::vector<double> v;
  for (const FrameTiming& f : frames) v.push_back(get(f));
  return summarize(v).median;
}

// "2.31 / 0.58 ms, 1.9%": the shadow pass and the frame per light (median wall time over K), and the checked
// lights' pooled misclassified pixels.
std::string cell(const CaseResult& r) {
  const double k = r.config.light_count;
  char buf[96];
  const double shadow = median_of(r.frames, [](const FrameTiming& f) { return f.shadow.cpu_wall_ms; });
  const double frame = median_of(r.frames, [](const FrameTiming& f) { return f.frame_wall_ms; });
  int n = std::snprintf(buf, sizeof buf, "%.2f / %.2f ms", shadow / k, frame / k);
  if (r.accuracy && r.accuracy->pixels > 0)
    std::snprintf(buf + n, sizeof buf - size_t(n), ", %.1f%%", r.accuracy->misclassified_percent);
  return buf;
}

}  // namespace

void light_count_table(std::ostringstream& md, const std::vector<CaseResult>& results) {
  std::set<int> counts;
  std::map<std::string, std::map<int, const CaseResult*>> rows;
  std::vector<std::string> order;
  for (const CaseResult& r : results) {
    if (r.frames.empty()) continue;
    counts.insert(r.config.light_count);
    const std::string key = row_key(r.config);
    if (!rows.count(key)) order.push_back(key);
    rows[key][r.config.light_count] = &r;
  }
  if (counts.size() < 2) return;
  md << "\n## Many lights: cost per light and error against the number of lights\n\n"
     << "Each cell: the shadow pass and the whole frame per light (median wall time / K) and the pixels "
        "misclassified against exact visibility, pooled over the lights checked (light 0, every "
        "stride-th and, above four lights, the farthest from the camera for its range: "
        "results.json accuracy.per_light). six_pass renders 6K passes, a single-pass technique K.\n\n"
     << "| case (K = 1 id) |";
  for (int k : counts) md << " " << k << (k == 1 ? " light" : " lights") << " |";
  md << "\n|---|";
  for (size_t i = 0; i < counts.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& key : order) {
    md << "| `" << key << "` |";
    for (int k : counts) md << " " << (rows[key].count(k) ? cell(*rows[key][k]) : "-") << " |";
    md << "\n";
  }
}

}  // namespace omnishadow::bench
