#include "bench/report/results_writer.h"

#include <cmath>
#include <set>

#include "backends/common/storage_filter_tables.h"
#include "bench/io/file_io.h"
#include "bench/report/check_reports_json.h"
#include "bench/run/memory_budget.h"
#include "bench/run/repetition_policy.h"
#include "bench/run/system_info.h"

namespace omnishadow::bench {
namespace {

using nlohmann::json;

json counters_to_json(const PassCounters& c) {
  json j{{"valid", c.valid}, {"draw_calls", c.draw_calls}};
  if (c.valid)
    for (const PipelineStatistic& s : kPipelineStatistics) j[s.name] = c.*s.member;
  return j;
}

json summary_to_json(const std::vector<double>& values) {
  Summary s = summarize(values);
  if (s.count == 0) return nullptr;
  return json{{"median", s.median}, {"mean", s.mean}, {"min", s.min},       {"max", s.max},
              {"p90", s.p90},       {"p99", s.p99},   {"stddev", s.stddev}, {"count", s.count}};
}

json pass_timing_to_json(const std::vector<FrameTiming>& frames, PassTiming FrameTiming::*pass,
                         bool gpu_reliable) {
  std::vector<double> wall, submit, gpu;
  for (const FrameTiming& f : frames) {
    wall.push_back((f.*pass).cpu_wall_ms);
    submit.push_back((f.*pass).cpu_submit_ms);
    gpu.push_back((f.*pass).gpu_ms);
  }
  return json{{"cpu_wall_ms", summary_to_json(wall)},
              {"cpu_submit_ms", summary_to_json(submit)},
              // Unreliable GPU figures are kept for inspection under another name, never as "gpu_ms".
              {gpu_reliable ? "gpu_ms" : "gpu_ms_unreliable", summary_to_json(gpu)}};
}

}  // namespace

json device_to_json(const DeviceInfo& d) {
  json j{{"api", d.api},
         {"vendor", d.vendor},
         {"renderer", d.renderer},
         {"version", d.version},
         {"platform", d.platform},
         {"max_cube_size", d.max_cube_size},
         {"subpixel_bits", d.subpixel_bits},
         {"subtexel_bits", d.subtexel_bits},
         {"device_memory_bytes", d.device_memory_bytes},
         {"shares_host_memory", d.shares_host_memory}};
  for (const auto& [k, v] : d.extra) j["extra"][k] = v;
  return j;
}

json axes_to_json(const CaseConfig& c) {
  json axes = {{"backend", c.backend},
               {"scene", c.scene},
               {"cube_size", c.cube_size},
               {"width", c.width},
               {"height", c.height},
               {"technique", to_string(c.technique)},
               {"filter", to_string(c.filter)},
               {"storage", to_string(c.storage)},
               {"depth_format", to_string(c.depth_format)},
               {"layout", to_string(c.layout)},
               {"tessellation", c.tessellation},
               {"light_count", c.light_count},
               {"light_grouping", to_string(c.light_grouping)},
               {"atlas_tiles", to_string(c.atlas_tiles)},
               {"shadow_budget_texels", c.shadow_budget_texels},
               {"atlas_replan_frames", c.atlas_replan_frames},
               {"atlas_hysteresis_octaves", c.atlas_hysteresis_octaves},
               {"update_budget_faces", c.update_budget_faces},
               {"optimizations", to_string(c.optimizations)},
               {"remedies", to_string(c.remedies)},
               {"moments_tuning", to_string(c.moments)},
               {"pcf_scale", c.pcf_scale}};
  if (!c.experiment.empty()) {  // only in sensitivity experiments (bench/run/matrix.h experiment axes)
    axes["experiment"] = c.experiment;
    axes["injected_fragment_work"] = c.injected_work;
  }
  if (c.raster_perturb_steps != 0.0f) axes["raster_perturb_steps"] = c.raster_perturb_steps;
  if (c.lookup_perturb_texels != 0.0f) axes["lookup_perturb_texels"] = c.lookup_perturb_texels;
  return axes;
}

namespace {

json scene_loads_json(const std::vector<SceneLoad>& loads) {
  json a = json::array();
  for (const SceneLoad& l : loads)
    a.push_back(
        {{"scene", l.name}, {"source", l.source}, {"triangles", l.triangles}, {"seconds", l.seconds}});
  return a;
}

// The run's injected fragment work: one number, or the sorted values when it was an experiment axis.
json injected_work_values(const std::vector<CaseResult>& results) {
  std::set<int> values;
  for (const CaseResult& r : results) values.insert(r.config.injected_work);
  if (values.size() <= 1) return values.empty() ? 0 : *values.begin();
  return json(std::vector<int>(values.begin(), values.end()));
}

// What the shadow pass was asked to do at the check frame, and the depth precision that follows from far.
json plan_to_json(const CaseResult& r) {
  json j = {
      {"object_face_pairs", r.object_face_pairs},
      {"empty_faces", r.empty_faces},
      {"light_far", r.light_far},
      {"storage_bytes", r.shadow_storage_bytes ? r.shadow_storage_bytes : shadow_storage_bytes(r.config)},
      {"texels", r.shadow_texels ? r.shadow_texels : shadow_texels(r.config)}};
  if (r.faces_rendered >= 0)
    j["rendered"] = {
        {"frame", "the frame counted (the check frame, or the next with caching or an update budget)"},
        {"faces", r.faces_rendered},
        {"texels", r.texels_rendered},
        {"passes", r.passes_rendered}};
  if (r.config.optimizations.view_culling)
    j["view_culling"] = {{"lights_culled", r.view_culled_lights}, {"faces_culled", r.view_culled_faces}};
  if (r.atlas) {
    std::vector<int> sizes;
    for (const atlas::Block& b : r.atlas->lights) sizes.push_back(b.face_size);
    j["atlas"] = {{"width", r.atlas->width},
                  {"height", r.atlas->height},
                  {"border", atlas::kBorder},
                  {"face_sizes", sizes}};
    if (r.config.atlas_replan_frames)  // the tiles of the check frame's re-plan
      j["atlas"]["planned_at_frame"] = r.atlas_planned_at;
    if (r.config.atlas_tiles == AtlasTiles::by_coverage) {
      j["atlas"]["budget_texels"] = atlas::budget_texels(r.config);
      j["atlas"]["budget_bytes"] = atlas::budget_texels(r.config) * shadow_bytes_per_texel(r.config);
      j["atlas"]["coverage"] = r.atlas_coverage;
    }
  }
  if (traits(r.config.storage).checked == DistanceEncoding::linear_depth) {
    // distance / far in [0, 1]: UNORM steps by 2^-bits; D32F by at most 2^-24 (its ulp just below 1).
    const int bits = r.config.depth_format == DepthFormat::d16 ? 16 : 24;
    j["depth_step_world"] = r.light_far / double(1u << bits);
  }
  return j;
}

// The floor, and each pass's median over it (wall time; GPU time where both are reliable).
json floor_to_json(const CaseResult& r) {
  const FrameTiming& f = *r.floor;
  auto gpu = [&](double v) { return r.gpu_timer.reliable && v > 0 ? json(v) : json(nullptr); };
  json j = {{"frames", kFloorFrames},
            {"shadow_wall_ms", f.shadow.cpu_wall_ms},
            {"lighting_wall_ms", f.lighting.cpu_wall_ms},
            {"shadow_gpu_ms", gpu(f.shadow.gpu_ms)},
            {"lighting_gpu_ms", gpu(f.lighting.gpu_ms)}};
  if (r.frames.empty()) return j;
  std::vector<double> shadow, lighting;
  for (const FrameTiming& t : r.frames) {
    shadow.push_back(t.shadow.cpu_wall_ms);
    lighting.push_back(t.lighting.cpu_wall_ms);
  }
  auto over = [](double v, double floor) { return floor > 0 ? json(v / floor) : json(nullptr); };
  j["shadow_over_floor"] = over(summarize(shadow).median, f.shadow.cpu_wall_ms);
  j["lighting_over_floor"] = over(summarize(lighting).median, f.lighting.cpu_wall_ms);
  return j;
}

// The per-repetition frame times, how sure their median is, and how stable they were
// (bench/run/repetition_policy.h).
json repetitions_to_json(const CaseResult& r) {
  MedianInterval ci = median_interval(r.precision_samples());
  json interval = nullptr;
  if (ci.defined)
    interval = {{"metric",
                 "frame_" + (r.precision_metric == "wall" ? std::string() : r.precision_metric + "_") + "ms"},
                {"median_ms", ci.median},
                {"low_ms", ci.low},
                {"high_ms", ci.high},
                {"coverage", ci.coverage},
                {"half_width_percent", ci.half_width_percent}};
  return {{"frame_ms", r.repetition_frame_ms},
          {"frame_cpu_ms", r.repetition_cpu_ms},
          {"frame_gpu_ms", r.repetition_gpu_ms},  // only repetitions whose GPU timer passed its check
          {"ended_by", r.repetitions_ended_by},
          {"precision_target_percent",
           r.precision_target_percent > 0 ? json(r.precision_target_percent) : json(nullptr)},
          {"median_interval_95", interval},
          {"stability_percent", stability_percent(r.repetition_frame_ms)}};
}

json timing_to_json(const CaseResult& r) {
  std::vector<double> frame_wall;
  for (const FrameTiming& f : r.frames) frame_wall.push_back(f.frame_wall_ms);
  return {{"repetitions", r.repetitions},
          {"timed_frames", r.frames.size()},
          {"frames_per_repetition", r.frames_per_repetition},
          {"warmup_frames", r.warmup.size()},
          {"frame_wall_ms", summary_to_json(frame_wall)},
          {"per_repetition", repetitions_to_json(r)},
          {"shadow", pass_timing_to_json(r.frames, &FrameTiming::shadow, r.gpu_timer.reliable)},
          {"lighting", pass_timing_to_json(r.frames, &FrameTiming::lighting, r.gpu_timer.reliable)}};
}

}  // namespace

json case_to_json(const CaseResult& r) {
  json j{{"id", r.config.id()},
         {"axes", axes_to_json(r.config)},
         {"status", to_string(r.status)},
         {"reason", r.reason},
         {"findings", json::array()}};
  for (const Finding& f : r.findings)
    j["findings"].push_back({{"status", to_string(f.status)},
                             {"check", f.check},
                             {"message", f.message},
                             {"figures", f.figures}});
  if (r.status == Status::unsupported) return j;
  j["counters"] = {{"shadow", counters_to_json(r.counters.shadow)},
                   {"lighting", counters_to_json(r.counters.lighting)}};
  j["checks"] = checks_to_json(r.checks);
  j["images"] = r.images;
  j["shadow_plan"] = plan_to_json(r);
  j["non_finite"] = {{"cube", r.non_finite_cube},
                     {"shadow_factor", r.non_finite_shadow},
                     {"world_position", r.non_finite_position}};
  if (r.flicker_percent)
    j["stability"] = {{"next_frame", "check_frame + 1"},
                      {"flicker_percent", *r.flicker_percent},
                      {"mean_abs_change", *r.flicker_mean_abs}};
  if (r.first_frame)
    j["first_frame"] = {{"shadow_wall_ms", r.first_frame->shadow.cpu_wall_ms},
                        {"lighting_wall_ms", r.first_frame->lighting.cpu_wall_ms},
                        {"frame_wall_ms", r.first_frame->frame_wall_ms}};
  if (r.accuracy) j["accuracy"] = accuracy_to_json(*r.accuracy);
  if (!r.per_light.empty()) j["accuracy"]["per_light"] = per_light_to_json(r);
  if (!r.untimed_ms.empty()) j["untimed_ms"] = r.untimed_ms;
  if (!r.cube_read_back.empty()) j["cube_read_back"] = r.cube_read_back;
  if (r.floor) j["floor"] = floor_to_json(r);
  add_check_reports(j, r);
  if (!r.device_states.empty()) {
    j["device_state"] = {{"source", r.device_state_source},
                         {"samples", json::array()},
                         {"warning", clock_warning(r.device_states)}};
    for (const DeviceState& d : r.device_states) j["device_state"]["samples"].push_back(to_json(d));
  }
  if (r.repetitions > 0) {
    j["timing"] = timing_to_json(r);
    j["gpu_timer"] = {{"available", r.gpu_timer.available},
                      {"reliable", r.gpu_timer.reliable},
                      {"frames_checked", r.gpu_timer.frames_checked},
                      {"frames_failing", r.gpu_timer.frames_failing},
                      {"note", r.gpu_timer.note}};
  }
  return j;
}

void write_results(const std::string& path, const RunInfo& run, const std::vector<CaseResult>& results,
                   const json& gbench, bool complete) {
  json out = gbench.is_object() ? gbench : json{{"context", json::object()}, {"benchmarks", json::array()}};
  std::map<std::string, const CaseResult*> by_id;
  for (const CaseResult& r : results) by_id[r.config.id()] = &r;
  // Each Google Benchmark entry points at its case and status; aggregates (_mean, ...) share run_name.
  for (json& b : out["benchmarks"]) {
    // Google Benchmark appends "/iterations:N/manual_time" (and "_mean" etc. to aggregate names).
    std::string run_name = b.value("run_name", b.value("name", ""));
    run_name = run_name.substr(0, run_name.find("/iterations:"));
    auto it = by_id.find(run_name);
    if (it != by_id.end()) {
      b["omnishadow_case"] = run_name;
      b["omnishadow_status"] = to_string(it->second->status);
    }
  }
  json cases = json::array();
  for (const CaseResult& r : results) cases.push_back(case_to_json(r));
  json devices = json::object();
  for (const auto& [name, d] : run.devices) devices[name] = device_to_json(d);
  const RunOptions& o = run.options;
  out["omnishadow"] = {
      {"format", "omnishadow-results/1"},
      {"complete", complete},
      {"stopped_by", run.stopped_by.empty() ? json(nullptr) : json(run.stopped_by)},
      {"shard", {{"index", run.shard_index}, {"count", run.shard_count}}},
      {"commit", build_commit()},
      {"commit_date", build_commit_date()},
      {"command_line", run.command_line},
      {"phases",
       {{"untimed_seconds",
         run.phases.untimed_seconds < 0 ? json(nullptr) : json(run.phases.untimed_seconds)},
        {"timed_seconds", run.phases.timed_seconds < 0 ? json(nullptr) : json(run.phases.timed_seconds)},
        {"scene_loads", scene_loads_json(run.phases.scene_loads)}}},
      {"repetition_policy",
       {{"timed", run.repetitions.timed},  // false: --no-timing, no case was timed
        {"repetitions", run.repetitions.repetitions},
        {"precision_percent", run.repetitions.precision_percent},
        {"max_repetitions", run.repetitions.max_repetitions},
        {"minimum", run.repetitions.minimum()},
        {"compared_cases", run.repetitions.compared_cases},
        {"sustain_seconds", run.repetitions.sustain_seconds},
        {"precision_metric", run.repetitions.metric},
        {"order", "rounds: one repetition of every unfinished case per round"}}},
      {"options",
       {{"warmup_frames", o.warmup_frames},
        {"warmup_ms", o.warmup_ms},  // negative: automatic (100 on a GPU, 0 on a CPU driver)
        {"settle_s", o.settle_s},
        {"repetition_ms", o.repetition_ms},  // negative: automatic (100 on a GPU, 0 on a CPU driver)
        {"injected_fragment_work", injected_work_values(results)},
        {"frames", o.frames},
        {"check_frame", o.check_frame},
        {"face_tolerance", o.face_tolerance},
        {"lit_tolerance", o.lit_tolerance},
        {"cross_lit_tolerance", o.cross_lit_tolerance},
        {"cross_shadow_tolerance", o.cross_shadow_tolerance},
        {"cross_max_percent", o.cross_max_percent},
        {"accuracy", o.accuracy},
        {"light_radius", o.truth.light_radius},
        {"light_samples", o.truth.samples_per_axis * o.truth.samples_per_axis},
        // --light / --camera: every scene's point light and camera were placed by hand
        {"light", o.light_text.empty() ? json(nullptr) : json(o.light_text)},
        {"camera", o.camera_text.empty() ? json(nullptr) : json(o.camera_text)}}},
      {"system", system_info()},
      {"devices", devices},
      {"cases", cases}};
  write_file_atomic(path, out.dump(2) + "\n");
}

}  // namespace omnishadow::bench
