#include "bench/run/gbench_glue.h"

#include <benchmark/benchmark.h>
#include <valgrind/callgrind.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <set>

#include "backends/common/driver_log.h"
#include "bench/run/case_progress.h"
#include "bench/run/gbench_report.h"
#include "bench/run/scripted_clock.h"

namespace omnishadow::bench {
namespace {

using benchmark::Counter;

double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// One frame with the process's CPU time around it (every thread: the driver's workers included), or the
// scripted clock's times (--inject-frame-ms).
FrameTiming render_measured(Backend& b, int frame, const RunOptions& o, const CaseConfig& config) {
  double before = process_cpu_ms();
  FrameTiming t = b.render(frame, FrameKind::timed);
  t.process_cpu_ms = process_cpu_ms() - before;
  apply_scripted_clock(o.inject_frame_ms, config.injected_work, t);
  return t;
}

void set_pass_counters(benchmark::State& state, const std::string& pass, const PassCounters& c) {
  if (!c.valid) return;
  // Work counters are per frame and identical every frame; kDefaults keeps them as-is. Named as in
  // results.json's "counters" section (the shared table), after the pass.
  state.counters[pass + "_draw_calls"] = Counter(static_cast<double>(c.draw_calls));
  for (const PipelineStatistic& s : kPipelineStatistics)
    state.counters[pass + "_" + s.name] = Counter(static_cast<double>(c.*s.member));
}

// One line per repetition on stderr: which round, which case, how far along.
struct Progress {
  const RepetitionPolicy& policy;
  int round = 0;
  int done = 0;  // repetitions so far, all cases
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  void step(const std::string& id, int in_round, int round_size) {
    ++done;
    std::string of = policy.cap() > 0 ? "/" + std::to_string(policy.cap()) : "";
    std::fprintf(stderr, "[time round %d%s, %d/%d] %s  (elapsed %.0fs)\n", round, of.c_str(), in_round,
                 round_size, id.c_str(), elapsed());
  }
};

constexpr int kMaxTimedWarmupFrames = 100000;  // --warmup-ms ends at this many frames whatever the time

// Renders `config`'s frames without a pause until the device clock reads steady (clock_steady: within 2% for
// a second, readings 50 ms apart) or `limit_s` passed; one line on stderr either way. Frame 0 again and
// again: untimed, nothing recorded.
void settle_clock(Harness& harness, const CaseConfig& config, double limit_s) {
  Backend& b = harness.activate(config);
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::vector<ClockReading> clocks{{0.0, harness.sample_device(config.backend).clock_mhz}};
  const std::string source = harness.device_state_source(config.backend);
  if (clocks.back().mhz <= 0) {
    std::fprintf(stderr, "[settle] %s: no clock reading (%s): timing without waiting for one\n",
                 config.backend.c_str(), source.c_str());
    return;
  }
  while (!clock_steady(clocks) && seconds() < limit_s) {
    b.render(0, FrameKind::timed);
    if (seconds() - clocks.back().seconds < 0.05) continue;
    clocks.push_back({seconds(), harness.sample_device(config.backend).clock_mhz});
  }
  double lo = clocks.back().mhz, hi = lo;
  for (const ClockReading& c : clocks)
    if (c.seconds >= clocks.back().seconds - 1.0) lo = std::min(lo, c.mhz), hi = std::max(hi, c.mhz);
  std::fprintf(
      stderr,
      "[settle] %s: clock %s at %.0f-%.0f MHz over the last second, after %.1f s (%s, started at %.0f MHz)\n",
      config.backend.c_str(), clock_steady(clocks) ? "steady" : "NOT steady", lo, hi, seconds(),
      source.c_str(), clocks.front().mhz);
}

// A frame's length as the sizing by time counts it: its wall time (scripted by --inject-frame-ms in tests).
double sizing_ms(const FrameTiming& frame) { return std::max(frame.frame_wall_ms, 0.0); }

// Timed frames per repetition for each case: RunOptions::frames, or more where a repetition of that many
// frames would last less than RunOptions::repetition_ms (measured here over a few frames after warm-up
// frames).
void size_repetitions(Harness& harness, std::vector<CaseResult>& results, const std::function<bool()>& stop) {
  const RunOptions& o = harness.options();
  for (CaseResult& r : results) {
    if (!is_timed(r.status) || stop()) continue;
    r.frames_per_repetition = o.frames;
    try {
      // The target first, from the device alone: a case is configured (activated) only when it is sized by
      // time, so CPU drivers (target 0) pay no extra configure per case.
      const double target_ms = o.repetition_ms >= 0
                                   ? o.repetition_ms
                                   : (harness.backend(r.config.backend).device().shares_host_memory
                                          ? 0.0
                                          : RunOptions::kGpuRepetitionMs);
      if (target_ms <= 0) continue;
      Backend& b = harness.activate(r.config);
      for (int i = 0; i < std::max(o.warmup_frames, 1); ++i) b.render(i, FrameKind::timed);
      double ms = 0.0;
      int n = 0;
      while (n < 3 || (ms < 10.0 && n < 100))
        ms += sizing_ms(render_measured(b, n++ % std::max(o.warmup_frames, 1), o, r.config));
      const double per_frame = std::max(ms / n, 1e-3);
      r.frames_per_repetition =
          std::clamp(static_cast<int>(std::ceil(target_ms / per_frame)), o.frames, kMaxTimedWarmupFrames);
    } catch (const std::exception&) {  // the case's own repetition reports the failure
    }
  }
}

// Warm-up frames: shader compilation on first use, caches, clocks. Never reported as timings. Then by time
// (RunOptions::warmup_ms), cycling over the same frame indices so that the timed frames stay the same frames.
// The time is the frames' own wall time as the backend measured it (each frame waits for the device), so the
// warm-up is as long as the frames it rendered, whatever the host's clock does between them, and a scripted
// device gives the same count on every machine.
void warm_up(Backend& b, const RunOptions& o, CaseResult& r) {
  double warmed_ms = 0.0;
  for (int i = 0; i < o.warmup_frames; ++i) {
    r.warmup.push_back(render_measured(b, i, o, r.config));
    warmed_ms += sizing_ms(r.warmup.back());
  }
  const double warmup_ms =
      o.warmup_ms >= 0 ? o.warmup_ms : (b.device().shares_host_memory ? 0.0 : RunOptions::kGpuWarmupMs);
  for (int i = 0; warmed_ms < warmup_ms && i < kMaxTimedWarmupFrames; ++i) {
    r.warmup.push_back(render_measured(b, o.warmup_frames > 0 ? i % o.warmup_frames : 0, o, r.config));
    warmed_ms += sizing_ms(r.warmup.back());
  }
}

// One repetition of one case: warm-up frames, then the timed frames Google Benchmark iterates over.
void time_case(Harness& harness, CaseResult& r, benchmark::State& state) {
  const RunOptions& o = harness.options();
  std::vector<FrameTiming> frames;
  send_progress(o.progress_fd, "timed " + r.config.id());
  try {
    inject_fault(o, r.config.id(), true);
    Backend& b = harness.activate(r.config);
    if (r.device_state_source.empty()) r.device_state_source = harness.device_state_source(r.config.backend);
    r.device_states.push_back(harness.sample_device(r.config.backend));  // before this repetition's frames
    warm_up(b, o, r);
    int frame = o.warmup_frames;
    double sums[7] = {0, 0, 0, 0, 0, 0, 0};
    // Under `valgrind --tool=callgrind --collect-atstart=no` (scripts/ci/instruction_counts.sh) exactly the
    // timed frames are counted, and each case's count is dumped under its id: instructions are a
    // deterministic measure of work on CPU drivers. Outside valgrind these requests are a few no-op
    // instructions.
    CALLGRIND_TOGGLE_COLLECT;
    for (auto _ : state) {
      FrameTiming t = render_measured(b, frame++, o, r.config);
      state.SetIterationTime(t.frame_wall_ms * 1e-3);
      sums[6] += t.process_cpu_ms;
      frames.push_back(t);
      sums[0] += t.shadow.cpu_wall_ms;
      sums[1] += t.shadow.cpu_submit_ms;
      sums[2] += t.lighting.cpu_wall_ms;
      sums[3] += t.lighting.cpu_submit_ms;
      sums[4] += t.shadow.gpu_ms;
      sums[5] += t.lighting.gpu_ms;
    }
    CALLGRIND_TOGGLE_COLLECT;
    // Named: the macro stores the pointer in one statement and issues the request in the next.
    const std::string dump_label = r.config.id() + " frames=" + std::to_string(frame - o.warmup_frames);
    CALLGRIND_DUMP_STATS_AT(dump_label.c_str());
    r.device_states.push_back(harness.sample_device(r.config.backend));  // after them
    std::vector<std::string> api_errors = b.drain_api_errors();          // outside the timed loop
    if (!api_errors.empty())
      throw std::runtime_error("API error (checking mode): " + std::to_string(api_errors.size()) +
                               " message(s): " + one_line_log(api_errors));
    state.counters["shadow_wall_ms"] = Counter(sums[0], Counter::kAvgIterations);
    state.counters["shadow_submit_ms"] = Counter(sums[1], Counter::kAvgIterations);
    state.counters["lighting_wall_ms"] = Counter(sums[2], Counter::kAvgIterations);
    state.counters["lighting_submit_ms"] = Counter(sums[3], Counter::kAvgIterations);
    state.counters["frame_cpu_ms"] = Counter(sums[6], Counter::kAvgIterations);  // compare --metric cpu
    std::vector<FrameTiming> checked = r.warmup;
    checked.insert(checked.end(), frames.begin(), frames.end());
    GpuTimerCheck gpu = check_gpu_timer(checked);
    state.counters["gpu_timer_reliable"] = Counter(gpu.reliable ? 1.0 : 0.0);
    if (gpu.reliable) {
      state.counters["shadow_gpu_ms"] = Counter(sums[4], Counter::kAvgIterations);
      state.counters["lighting_gpu_ms"] = Counter(sums[5], Counter::kAvgIterations);
      if (!frames.empty())
        r.repetition_gpu_ms.push_back((sums[4] + sums[5]) / static_cast<double>(frames.size()));
    }
    set_pass_counters(state, "shadow", r.counters.shadow);
    set_pass_counters(state, "lighting", r.counters.lighting);
    state.SetLabel(std::string(to_string(r.status)));
  } catch (const std::exception& e) {
    r.add({Status::failed, "timing", std::string("while timing: ") + e.what(), {}});
    state.SkipWithError(("failed: " + r.reason).c_str());
  }
  r.frames.insert(r.frames.end(), frames.begin(), frames.end());
  if (!frames.empty()) {
    double wall = 0.0, cpu = 0.0;
    for (const FrameTiming& t : frames) wall += t.frame_wall_ms, cpu += t.process_cpu_ms;
    r.repetition_frame_ms.push_back(wall / static_cast<double>(frames.size()));
    r.repetition_cpu_ms.push_back(cpu / static_cast<double>(frames.size()));
  }
  ++r.repetitions;
  std::vector<FrameTiming> all = r.warmup;
  all.insert(all.end(), r.frames.begin(), r.frames.end());
  r.gpu_timer = check_gpu_timer(all);
}

// The cases that get another repetition this round (matrix order; Google Benchmark may shuffle it).
std::vector<CaseResult*> next_round(std::vector<CaseResult>& results, const RepetitionPolicy& policy,
                                    double elapsed) {
  std::vector<CaseResult*> out;
  for (CaseResult& r : results)
    if (is_timed(r.status) && needs_repetition(policy, r.precision_samples(), elapsed)) out.push_back(&r);
  return out;
}

std::string ended_by(const RepetitionPolicy& policy, const CaseResult& r, bool stopped, double elapsed) {
  if (!needs_repetition(policy, r.precision_samples(), elapsed)) {
    if (policy.sustain_seconds > 0.0) return "sustain";
    if (policy.precision_percent <= 0.0) return "count";
    return r.repetitions >= policy.cap() &&
                   median_interval(r.precision_samples()).half_width_percent > policy.precision_percent
               ? "cap"
               : "precision";
  }
  return stopped ? "stopped" : "count";
}

}  // namespace

bool is_timed(Status s) {
  return s == Status::ok || s == Status::failed_check || s == Status::failed_quality;
}

size_t compared_cases(const std::vector<CaseResult>& results) {
  std::set<std::string> ids;
  for (const CaseResult& r : results) {
    if (!is_timed(r.status)) continue;
    CaseConfig c = r.config;
    c.experiment.clear();
    ids.insert(c.id());
  }
  return ids.size();
}

void run_timed(Harness& harness, std::vector<CaseResult>& results, const RepetitionPolicy& policy,
               const std::string& gbench_json_path, const std::function<void()>& after_case,
               const std::function<bool()>& stop_requested) {
  Progress progress{policy};
  RoundReporter reporter;
  for (CaseResult& r : results) r.precision_metric = policy.metric;
  const int frames = harness.options().frames;
  // Each backend's clock settles before its first timed repetition (rounds interleave the backends' cases).
  if (harness.options().settle_s > 0) {
    std::set<std::string> settled;
    for (CaseResult& r : results)
      if (is_timed(r.status) && settled.insert(r.config.backend).second && !stop_requested()) {
        try {
          settle_clock(harness, r.config, harness.options().settle_s);
        } catch (const std::exception& e) {  // the case's own repetition reports any failure
          std::fprintf(stderr, "[settle] %s: %s\n", r.config.backend.c_str(), e.what());
        }
      }
  }
  size_repetitions(harness, results, stop_requested);
  for (;;) {
    std::vector<CaseResult*> round = next_round(results, policy, progress.elapsed());
    if (round.empty() || stop_requested()) break;
    ++progress.round;
    int in_round = 0;
    for (CaseResult* r : round)
      benchmark::RegisterBenchmark(r->config.id().c_str(),
                                   [&, r, size = static_cast<int>(round.size())](benchmark::State& state) {
                                     // A stop ends the run after the repetition in hand, not after the round:
                                     // the rest of the round is skipped (RoundReporter drops skipped runs).
                                     if (stop_requested()) {
                                       state.SkipWithError("stopped");
                                       return;
                                     }
                                     progress.step(r->config.id(), ++in_round, size);
                                     time_case(harness, *r, state);
                                     after_case();
                                   })
          ->UseManualTime()
          ->Iterations(r->frames_per_repetition > 0 ? r->frames_per_repetition : frames)
          ->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();
  }
  const bool stopped = stop_requested();
  for (CaseResult& r : results) {
    if (r.repetitions == 0) {
      if (is_timed(r.status) && stopped)
        r.add({Status::interrupted,
               "timing",
               "interrupted: the run was stopped before this case was timed",
               {}});
      continue;
    }
    r.precision_target_percent = policy.precision_percent;
    r.repetitions_ended_by = ended_by(policy, r, stopped, progress.elapsed());
  }
  write_gbench_json(gbench_json_path, reporter.all_runs());
}

}  // namespace omnishadow::bench
