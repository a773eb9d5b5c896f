#include "bench/report/summary_table.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include "backends/common/storage_filter_tables.h"
#include "bench/io/statistics.h"
#include "bench/report/light_count_table.h"
#include "bench/run/timing_stats.h"

namespace omnishadow::bench {
namespace {

Summary summary_of(const std::vector<FrameTiming>& frames, double (*get)(const FrameTiming&)) {
  std::vector<double> v;
  for (const FrameTiming& f : frames) v.push_back(get(f));
  return summarize(v);
}

double shadow_wall(const FrameTiming& f) { return f.shadow.cpu_wall_ms; }
double lighting_wall(const FrameTiming& f) { return f.lighting.cpu_wall_ms; }

// "7.51 ms (1.00x) p99/median 1.3x": the median, its ratio to the base column, and p99 / median of the same
// frames, labelled as the ratio it is (a technique faster on median that stutters shows a large one).
std::string cell(const Summary& s, double base) {
  char buf[80];
  if (s.median <= 0 || base <= 0) return "-";
  std::snprintf(buf, sizeof buf, "%.2f ms (%.2fx) p99/median %.1fx", s.median, s.median / base,
                s.p99 / s.median);
  return buf;
}

// The axes a pass's cost depends on, as a row key: the shadow pass does not depend on the filter and the
// lighting pass not on the technique, so each row pools every case of its group over the other axis.
std::string pass_group(const CaseConfig& c) {
  return c.backend + "/" + c.scene + "/c" + std::to_string(c.cube_size) + "/f" + std::to_string(c.width) +
         "x" + std::to_string(c.height) + "/" + std::string(to_string(c.storage)) + "/" +
         std::string(to_string(c.depth_format)) +
         (c.layout == Layout::cube ? std::string() : "/" + std::string(to_string(c.layout))) +
         (c.tessellation == 1 ? std::string() : "/t" + std::to_string(c.tessellation)) +
         (c.light_count == 1 ? std::string() : "/l" + std::to_string(c.light_count)) +
         (c.light_grouping == LightGrouping::per_light ? std::string() : "/all_lights") + c.atlas_tiling_id();
}

// One row per pass group, one column per value of `axis`: the median of `metric` over all timed frames of the
// group's cases with that value, its ratio to the `base` column, and p99 / median.
template <typename E>
void ratio_table(std::ostringstream& md, const std::vector<CaseResult>& results, const std::string& title,
                 E CaseConfig::*axis, E base, double (*metric)(const FrameTiming&)) {
  // A run that timed no case (every one unsupported, failed or crashed) has no row to show: no table.
  if (std::none_of(results.begin(), results.end(), [](const CaseResult& r) { return !r.frames.empty(); }))
    return;
  const std::vector<E> values = all_values<E>();
  md << "\n## " << title << "\n\n| backend/scene/cube/frame/storage/depth |";
  for (E v : values) md << " " << to_string(v) << " |";
  md << "\n|---|";
  for (size_t i = 0; i < values.size(); ++i) md << "---|";
  md << "\n";
  std::map<std::string, std::map<E, std::vector<FrameTiming>>> by_group;
  std::vector<std::string> group_order;
  for (const CaseResult& r : results) {
    if (r.frames.empty()) continue;
    std::string key = pass_group(r.config);
    if (!by_group.count(key)) group_order.push_back(key);
    auto& frames = by_group[key][r.config.*axis];
    frames.insert(frames.end(), r.frames.begin(), r.frames.end());
  }
  for (const std::string& key : group_order) {
    auto& row = by_group[key];
    double base_value = row.count(base) ? summary_of(row[base], metric).median : 0.0;
    md << "| `" << key << "` |";
    for (E v : values)
      md << " " << (row.count(v) ? cell(summary_of(row[v], metric), base_value) : "-") << " |";
    md << "\n";
  }
}

// The axes a shadow's accuracy depends on beyond its pass group: the PCF scale, remedies and moments tunings
// (the techniques are held to six_pass bit for bit, so the first case of a row speaks for all of them).
std::string accuracy_group(const CaseConfig& c) {
  std::string key = pass_group(c);
  char buf[32];
  if (c.pcf_scale != 1.0f) {
    std::snprintf(buf, sizeof buf, "/pcf%g", double(c.pcf_scale));
    key += buf;
  }
  if (c.remedies.any()) key += "/" + to_string(c.remedies);
  if (c.moments.any()) key += "/" + to_string(c.moments);
  return key;
}

// "0.195% / 0.0020 / r 0.05 (0.0113)": misclassified, MAE against the point light, the best-fitting spherical
// light's radius and its MAE.
std::string accuracy_cell(const Accuracy& a) {
  char buf[96];
  if (a.fit_radius >= 0)
    std::snprintf(buf, sizeof buf, "%.3g%% / %.4f / r %.3g (%.4f)", a.misclassified_percent, a.mae_point,
                  a.fit_radius, a.fit_mae_best);
  else
    std::snprintf(buf, sizeof buf, "%.3g%% / %.4f", a.misclassified_percent, a.mae_point);
  return buf;
}

// Per group, per filter: what the filter's shadow costs in accuracy, against what it is held to.
void accuracy_table(std::ostringstream& md, const std::vector<CaseResult>& results) {
  std::map<std::string, std::map<Filter, const Accuracy*>> rows;
  std::vector<std::string> order;
  for (const CaseResult& r : results) {
    if (!r.accuracy || r.accuracy->pixels == 0) continue;
    const std::string key = accuracy_group(r.config);
    if (!rows.count(key)) order.push_back(key);
    rows[key].emplace(r.config.filter, &*r.accuracy);  // the first case of the row (six_pass comes first)
  }
  if (order.empty()) return;
  const std::vector<Filter> filters = all_values<Filter>();
  md << "\n## Accuracy per filter, against exact visibility\n\n"
     << "Each cell: misclassified pixels (shadow factor on the other side of 0.5 from the point light's "
        "exact "
        "visibility) / mean absolute difference from that visibility / r: the radius of the spherical light "
        "whose exact soft shadow the filter matches best, with that mean error. A soft filter blurs the "
        "point "
        "light's edge by design: judge it by its fit, hard by the first two.\n\n"
     << "| backend/scene/cube/frame/storage/depth |";
  for (Filter f : filters) md << " " << to_string(f) << " |";
  md << "\n|---|";
  for (size_t i = 0; i < filters.size(); ++i) md << "---|";
  md << "\n";
  for (const std::string& key : order) {
    md << "| `" << key << "` |";
    for (Filter f : filters) md << " " << (rows[key].count(f) ? accuracy_cell(*rows[key][f]) : "-") << " |";
    md << "\n";
  }
}

// Beyond this share of pixels, a hard filter's false or missed shadows are named in summary.md: a correct
// cube still shows some at silhouettes and grazing receivers, and the quality limit (5%) fails a case long
// after a user should have been told why its image looks wrong.
constexpr double kDiagnosePercent = 1.0;

// What the errors of the filters that are not soft by design (hard, hw_compare2x2) are, where they are many:
// acne (shadowed where the light is visible: the bias is short of the depth a texel spans on grazing
// receivers) or leaks (lit where the light is hidden: peter-panning, light through a thin caster), with what
// mends each. A model placed by the rule is held to the tutorials' world-unit biases: this is where the run
// says they do not hold.
void diagnoses(std::ostringstream& md, const std::vector<CaseResult>& results) {
  std::map<std::string, std::string> lines;  // by group and filter: the first case speaks for its techniques
  for (const CaseResult& r : results) {
    if (!r.accuracy || r.accuracy->pixels == 0 || traits(r.config.filter).soft) continue;
    const std::string key = accuracy_group(r.config) + "/" + std::string(to_string(r.config.filter));
    const Accuracy& a = *r.accuracy;
    char buf[160];
    std::string line;
    if (a.false_shadow_percent >= kDiagnosePercent) {
      std::snprintf(buf, sizeof buf, "%.2f%% of pixels shadowed where the light is visible (acne)",
                    a.false_shadow_percent);
      line =
          std::string(buf) +
          ": the lookup's bias is short of the depth a texel spans on grazing receivers at cube " +
          std::to_string(r.config.cube_size) +
          "; a bigger cube, a PCF filter or --remedy normal_offset (which trades some for leaks) mends it, "
          "the slope bias does not (it is smaller than the tutorial's on most receivers)";
    }
    if (a.missed_shadow_percent >= kDiagnosePercent) {
      std::snprintf(buf, sizeof buf, "%.2f%% of pixels lit where the light is hidden (leaks)",
                    a.missed_shadow_percent);
      line +=
          (line.empty() ? "" : "; ") + std::string(buf) +
          ": the bias moves shadows off their casters' feet (peter-panning) or a caster is thinner than "
          "it; a smaller bias (--remedy slope_bias, which trades some for acne) or --remedy two_sided for "
          "a light inside a closed caster mends it";
    }
    if (!line.empty()) lines.emplace(key, "- `" + r.config.id() + "`: " + line + "\n");
  }
  if (lines.empty()) return;
  md << "\n## What the errors are\n\n";
  for (const auto& [key, line] : lines) md << line;
}

// The staleness sequences (--update-budget, --staleness-frames): what refreshing fewer faces a frame costs,
// and with atlas re-plans (--atlas-replan) the lights they moved, each a whole light's render again.
void staleness_table(std::ostringstream& md, const std::vector<CaseResult>& results) {
  const bool replans = std::any_of(results.begin(), results.end(), [](const CaseResult& r) {
    return r.staleness && !r.staleness->frames.empty() && r.config.atlas_replan_frames > 0;
  });
  std::ostringstream rows;
  for (const CaseResult& r : results) {
    if (!r.staleness || r.staleness->frames.empty()) continue;
    const StalenessReport& s = *r.staleness;
    char buf[200];
    std::snprintf(buf, sizeof buf, "| %zu | %.1f | %d (bound %d) | ", s.frames.size(), s.mean_faces_rendered,
                  s.max_wait, s.wait_bound);
    rows << "| `" << r.config.id() << "` " << buf;
    if (s.lights.empty()) {  // --no-accuracy: no error measured
      rows << "- | - |";
    } else {
      std::snprintf(buf, sizeof buf, "%.3g%% | %.3g%% (frame %d) |", s.mean_misclassified_percent,
                    s.worst_misclassified_percent, s.worst_frame);
      rows << buf;
    }
    if (replans) {
      int moved = 0, moving = 0;
      for (const StalenessFrame& f : s.frames) moved += f.lights_relocated, moving += f.lights_relocated > 0;
      if (r.config.atlas_replan_frames > 0)
        rows << " " << moved << " (" << moving << ") |";
      else
        rows << " - |";
    }
    rows << "\n";
  }
  if (rows.str().empty()) return;
  md << "\n## Staleness over a sequence of frames\n\n"
     << "Frames 0..N-1 from a fresh start; a face waits while it is read holding an older position of its "
        "light. Misclassified: the lights that move and those checked, against each frame's exact "
        "visibility."
     << (replans ? " Moved: the lights whose atlas block a re-plan moved or resized over the sequence (the "
                   "frames that moved any), each rendered whole again."
                 : "")
     << "\n\n"
     << "| case | frames | faces rendered a frame after the first | longest wait, frames | misclassified, "
        "mean | worst |"
     << (replans ? " moved by re-plans |" : "") << "\n"
     << "|---|---|---|---|---|---|" << (replans ? "---|" : "") << "\n"
     << rows.str();
}

// Every timed case's passes as multiples of their floor (the same render passes with nothing drawn; the frame
// shaded with a constant): how far a technique or filter is from what the device does at all.
void floor_table(std::ostringstream& md, const std::vector<CaseResult>& results) {
  std::ostringstream rows;
  for (const CaseResult& r : results) {
    if (!r.floor || r.frames.empty()) continue;
    const double shadow = summary_of(r.frames, shadow_wall).median,
                 lighting = summary_of(r.frames, lighting_wall).median;
    char buf[200];
    std::snprintf(buf, sizeof buf, "| `%s` | %.2f ms = %.1fx %.2f | %.2f ms = %.1fx %.2f |\n",
                  r.config.id().c_str(), shadow,
                  r.floor->shadow.cpu_wall_ms > 0 ? shadow / r.floor->shadow.cpu_wall_ms : 0.0,
                  r.floor->shadow.cpu_wall_ms, lighting,
                  r.floor->lighting.cpu_wall_ms > 0 ? lighting / r.floor->lighting.cpu_wall_ms : 0.0,
                  r.floor->lighting.cpu_wall_ms);
    rows << buf;
  }
  if (rows.str().empty()) return;
  md << "\n## Passes against their floor (median wall time = multiple x floor)\n\n"
     << "Floor: the case's shadow render passes cleared with nothing drawn; the frame shaded with a "
        "constant.\n\n"
     << "| case | shadow pass | lighting pass |\n|---|---|---|\n"
     << rows.str();
}

// Under --precision: the interval each case reached and the cases that hit the cap. Under --sustain: each
// case's worst repetition against its best, the clocks it ran at, and the cases below kStabilityPassPercent.
void repetition_table(std::ostringstream& md, const std::vector<CaseResult>& results,
                      const RepetitionPolicy& p) {
  if (p.precision_percent <= 0.0 && p.sustain_seconds <= 0.0) return;
  int total = 0, capped = 0, unstable = 0;
  std::ostringstream rows;
  for (const CaseResult& r : results) {
    if (r.repetition_frame_ms.empty()) continue;
    total += static_cast<int>(r.repetition_frame_ms.size());
    MedianInterval ci = median_interval(r.precision_samples());
    const double stability = stability_percent(r.repetition_frame_ms);
    auto [best, worst] = std::minmax_element(r.repetition_frame_ms.begin(), r.repetition_frame_ms.end());
    capped += r.repetitions_ended_by == "cap";
    unstable += stability < kStabilityPassPercent;
    char buf[320];
    if (p.sustain_seconds > 0.0)
      std::snprintf(buf, sizeof buf, "| `%s` | %zu | %.3f | %.3f | %.1f%%%s | %s |\n", r.config.id().c_str(),
                    r.repetition_frame_ms.size(), *best, *worst, stability,
                    stability < kStabilityPassPercent ? " **below 97%**" : "",
                    clock_range(r.device_states).c_str());
    else
      std::snprintf(
          buf, sizeof buf, "| `%s` | %zu | %.3f | %s | %s |\n", r.config.id().c_str(),
          r.repetition_frame_ms.size(), ci.median,
          ci.defined ? ("+-" + std::to_string(ci.half_width_percent).substr(0, 5) + "%").c_str() : "-",
          r.repetitions_ended_by.c_str());
    rows << buf;
  }
  if (p.sustain_seconds > 0.0) {
    md << "\n## Sustained run (" << p.sustain_seconds << " s of rounds): best repetition / worst\n\n"
       << total << " repetitions; " << unstable << " cases below " << kStabilityPassPercent
       << "% (per-repetition mean frame time, shortest over longest)\n\n"
       << "| case | repetitions | best ms | worst ms | stability | clocks |\n|---|---|---|---|---|---|\n";
  } else {
    md << "\n## Repetitions to +-" << p.precision_percent
       << "% (95% interval of the median per-repetition frame "
       << (p.metric == "wall"  ? "wall"
           : p.metric == "cpu" ? "CPU"
                               : "GPU")
       << " time)\n\n"
       << total << " repetitions in all (a fixed count of " << p.cap() << " would take "
       << p.cap() * static_cast<int>(
                        std::count_if(results.begin(), results.end(),
                                      [](const CaseResult& r) { return !r.repetition_frame_ms.empty(); }))
       << "); " << capped << " cases hit the cap of " << p.cap() << "; at least " << p.minimum()
       << " each (never fewer than `omnishadow compare` over " << p.compared_cases << " cases at alpha "
       << kDefaultAlpha << " needs to flag one)\n\n"
       << "| case | repetitions | median ms | reached | ended by |\n|---|---|---|---|---|\n";
  }
  md << rows.str();
}

}  // namespace

std::string summary_markdown(const std::vector<CaseResult>& results, const RunPhases& phases,
                             const RepetitionPolicy& policy, const std::string& incomplete) {
  std::ostringstream md;
  std::map<std::string, int> status_counts;
  for (const CaseResult& r : results) ++status_counts[std::string(to_string(r.status))];
  if (!incomplete.empty())
    md << "**Incomplete run: " << incomplete << ".** Cases it did not time are `interrupted`; the figures "
       << "below are of what ran, and compare counts the cases it lacks as missing.\n\n";
  md << "## Cases\n\n";
  if (!policy.timed) md << "Not timed (`--no-timing`): the checks, the reference and the images only.\n\n";
  if (phases.untimed_seconds >= 0 && phases.timed_seconds >= 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "Run: %.1f s untimed (checks, read-backs, reference, images) + %.1f s timed",
                  phases.untimed_seconds, phases.timed_seconds);
    md << buf;
    // The ratio only where both parts are long enough to read at this precision: a matrix of unsupported
    // cases spends microseconds in each, and their ratio says nothing.
    if (phases.untimed_seconds >= 0.05 && phases.timed_seconds >= 0.05) {
      std::snprintf(buf, sizeof buf, " (%.2fx the timed part)",
                    phases.untimed_seconds / phases.timed_seconds);
      md << buf;
    }
    md << "\n\n";
  }
  if (!phases.scene_loads.empty()) {
    md << "Scenes loaded before the untimed part (parse, bake, bounds):";
    for (const SceneLoad& load : phases.scene_loads) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " %.2f s for %llu triangles", load.seconds,
                    static_cast<unsigned long long>(load.triangles));
      md << " " << load.name << buf << (&load == &phases.scene_loads.back() ? "" : ";");
    }
    md << "\n\n";
  }
  std::map<std::string, double> steps;  // the untimed part's seconds per step, all cases
  for (const CaseResult& r : results)
    for (const auto& [name, ms] : r.untimed_ms) steps[name] += ms / 1000.0;
  if (!steps.empty()) {
    md << "Untimed part by step:";
    for (const auto& [name, seconds] : steps) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " %s %.1f s", name.c_str(), seconds);
      md << buf << (name == steps.rbegin()->first ? "" : ",");
    }
    md << "\n\n";
  }
  for (const auto& [status, count] : status_counts) md << "- " << status << ": " << count << "\n";
  // Unsupported cases once per reason (a GL run asking for multiview gave one line per case before).
  std::map<std::string, std::vector<std::string>> unsupported;
  for (const CaseResult& r : results)
    if (r.status == Status::unsupported) unsupported[r.reason].push_back(r.config.id());
  for (const auto& [reason, ids] : unsupported)
    md << "  - unsupported, " << ids.size() << (ids.size() == 1 ? " case" : " cases") << " (e.g. `"
       << ids.front() << "`): " << reason << "\n";
  for (const CaseResult& r : results)
    if (r.status != Status::ok && r.status != Status::unsupported)
      md << "  - `" << r.config.id() << "` " << to_string(r.status) << ": " << r.reason << "\n";
  // A figure measured while the clock moved is not the device's figure: say so next to the statuses.
  for (const CaseResult& r : results)
    if (std::string w = clock_warning(r.device_states); !w.empty())
      md << "- **warning** `" << r.config.id() << "`: " << w << " (" << r.device_state_source << ")\n";

  accuracy_table(md, results);
  light_count_table(md, results);
  diagnoses(md, results);
  repetition_table(md, results, policy);
  floor_table(md, results);
  staleness_table(md, results);
  if (!policy.timed) return md.str();
  ratio_table<Technique>(
      md, results, "Shadow pass: median wall time per technique, all filters pooled (ratio to six_pass)",
      &CaseConfig::technique, Technique::six_pass, shadow_wall);
  ratio_table<Filter>(md, results,
                      "Lighting pass: median wall time per filter, all techniques pooled (ratio to hard)",
                      &CaseConfig::filter, Filter::hard, lighting_wall);
  return md.str();
}

}  // namespace omnishadow::bench
