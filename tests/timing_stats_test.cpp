// Timing summaries and the GPU-timer sanity check.

#include "bench/run/timing_stats.h"

#include <gtest/gtest.h>

#include "bench/run/device_state.h"
#include "bench/run/repetition_policy.h"

namespace omnishadow::bench {
namespace {

FrameTiming frame(double shadow_wall, double shadow_gpu, double lighting_wall, double lighting_gpu) {
  FrameTiming f;
  f.shadow = {shadow_wall / 2, shadow_wall, shadow_gpu};
  f.lighting = {lighting_wall / 2, lighting_wall, lighting_gpu};
  f.frame_wall_ms = shadow_wall + lighting_wall;
  return f;
}

TEST(TimingStats, Summary) {
  Summary s = summarize({4, 1, 3, 2});
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_NEAR(s.stddev, 1.2909944, 1e-6);
  EXPECT_EQ(summarize({}).count, 0);
}

TEST(TimingStats, GpuFiguresWithinWallTimeAreTrusted) {
  GpuTimerCheck c = check_gpu_timer({frame(10, 9.5, 5, 4.9), frame(10, 10.2, 5, 5)});  // 10.2 within slack
  EXPECT_TRUE(c.available);
  EXPECT_TRUE(c.reliable);
  EXPECT_EQ(c.frames_checked, 2);
}

TEST(TimingStats, ImpossibleGpuFiguresAreFlagged) {
  // llvmpipe's first GL_TIME_ELAPSED after context creation: ~5e5 ms for a 90 ms pass.
  GpuTimerCheck c = check_gpu_timer({frame(92.6, 516371.5, 20, 19), frame(10, 9, 5, 4)});
  EXPECT_FALSE(c.reliable);
  EXPECT_EQ(c.frames_failing, 1);
  EXPECT_NE(c.note.find("shadow pass: gpu 516371.500 ms"), std::string::npos) << c.note;
  EXPECT_FALSE(check_gpu_timer({frame(10, 0, 5, 4)}).reliable);  // zero is no measurement
}

TEST(TimingStats, NoGpuFiguresIsNotReliable) {
  GpuTimerCheck c = check_gpu_timer({frame(10, -1, 5, -1)});
  EXPECT_FALSE(c.available);
  EXPECT_FALSE(c.reliable);
}

}  // namespace
}  // namespace omnishadow::bench

namespace omnishadow::bench {
namespace {

TEST(Summary, PercentilesOfEveryFrame) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);  // 1..100
  Summary s = summarize(v);
  EXPECT_DOUBLE_EQ(s.median, 50.5);
  EXPECT_NEAR(s.p90, 90.1, 1e-9);  // numpy.percentile(range(1, 101), 90)
  EXPECT_NEAR(s.p99, 99.01, 1e-9);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  // One stutter among steady frames: the median does not see it, p99 and max do.
  std::vector<double> steady(99, 10.0);
  steady.push_back(50.0);
  Summary t = summarize(steady);
  EXPECT_DOUBLE_EQ(t.median, 10.0);
  EXPECT_GT(t.p99, 10.0);
  EXPECT_DOUBLE_EQ(t.max, 50.0);
  EXPECT_DOUBLE_EQ(quantile_sorted({}, 0.5), 0.0);
}

}  // namespace
}  // namespace omnishadow::bench

namespace omnishadow::bench {
namespace {

TEST(DeviceState, ClockWarningOnlyWhenTheClockMovedOrThrottled) {
  DeviceState idle, boost, steady;
  idle.clock_mhz = 345;
  boost.clock_mhz = 1980;
  steady.clock_mhz = 1965;  // within 5% of 1980
  // Samples come in pairs, before and after each timed repetition.
  EXPECT_EQ(clock_warning({boost, steady, steady, boost}), "");
  EXPECT_EQ(clock_warning({idle, boost}), "clocks moved inside 1 of 1 timed repetitions: 345-1980 MHz");
  EXPECT_EQ(clock_warning({idle, idle, boost, boost, boost, steady}), "")
      << "a clock that differs between repetitions, steady inside each, measured each figure at one clock";
  EXPECT_EQ(clock_warning({boost, boost, idle, boost, boost, boost}),
            "clocks moved inside 1 of 3 timed repetitions: 345-1980 MHz");
  DeviceState hot = boost;
  hot.throttle = "hw_thermal_slowdown";
  EXPECT_EQ(clock_warning({boost, hot}), "throttled: hw_thermal_slowdown");
  EXPECT_EQ(clock_warning({DeviceState{}, DeviceState{}}), "") << "unknown clocks say nothing";
  EXPECT_FALSE(to_json(hot).contains("temperature_c")) << "unknown fields are left out";
  EXPECT_EQ(to_json(hot)["clock_mhz"], 1980);
}

// Readings 50 ms apart, as settle_clock takes them.
std::vector<ClockReading> every_50ms(const std::vector<double>& mhz) {
  std::vector<ClockReading> out;
  for (size_t i = 0; i < mhz.size(); ++i) out.push_back({0.05 * static_cast<double>(i), mhz[i]});
  return out;
}

TEST(DeviceState, ClockSteadyWhenTheReadingsAgreeForTheWholeWindow) {
  EXPECT_FALSE(clock_steady(every_50ms({345, 345, 345})))
      << "the H200's idle clock over its first 0.1 s of rendering is not steady: the readings must span the "
         "window";
  EXPECT_FALSE(clock_steady(every_50ms(std::vector<double>(20, 1980)))) << "0.95 s: short of the 1 s window";
  EXPECT_TRUE(clock_steady(every_50ms(std::vector<double>(21, 1980))));
  std::vector<double> ramp{345, 630, 1125, 1755};
  ramp.insert(ramp.end(), 20, 1980);
  EXPECT_FALSE(clock_steady(every_50ms(ramp))) << "the last 1755 MHz reading is inside the window";
  ramp.push_back(1965);
  EXPECT_TRUE(clock_steady(every_50ms(ramp))) << "within 2% over the last second";
  std::vector<double> drop(21, 1980);
  drop[10] = 1890;
  EXPECT_FALSE(clock_steady(every_50ms(drop))) << "4.5% below inside the window";
  EXPECT_FALSE(clock_steady(every_50ms(std::vector<double>(30, -1)))) << "an unknown clock never settles";
  EXPECT_TRUE(clock_steady({{0.0, 1125}, {2.0, 1125}}, 1.0)) << "sparse readings spanning the window";
}

// Here (no GPU) the probe reads the CPUs' frequency; on any machine it names its source and never throws.
TEST(DeviceState, ProbeNamesItsSource) {
  DeviceInfo cpu;
  cpu.renderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
  cpu.shares_host_memory = true;
  auto probe = make_device_state_probe(cpu);
  EXPECT_EQ(probe->source(), "cpu frequency");
  DeviceState s = probe->sample();
  if (s.clock_mhz < 0) GTEST_SKIP() << "this machine publishes no CPU frequency (/proc/cpuinfo, cpufreq)";
  EXPECT_GT(s.clock_mhz, 100.0);
}

}  // namespace
}  // namespace omnishadow::bench

#include <atomic>
#include <stdexcept>

#include "bench/run/async_writer.h"

namespace omnishadow::bench {
namespace {

TEST(AsyncWriter, RunsEveryJobAndNamesTheOnesThatFailed) {
  std::atomic<int> done{0};
  AsyncWriter writer(2);  // a small queue: submit waits for room instead of growing
  for (int i = 0; i < 20; ++i)
    writer.submit("case" + std::to_string(i), [&done, i] {
      if (i == 7) throw std::runtime_error("disk full");
      ++done;
    });
  auto failures = writer.drain();
  EXPECT_EQ(done.load(), 19);
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].first, "case7");
  EXPECT_EQ(failures[0].second, "disk full");
  EXPECT_TRUE(writer.drain().empty()) << "reported once";
}

// The sign-test interval: n = 6 takes the extremes (coverage 1 - 2/64); n = 9 ranks 2 and 8 (1 - 2 * 10/512);
// fewer than 6 samples cannot bracket the median at 95%.
TEST(RepetitionPolicy, MedianIntervalUsesBinomialOrderStatistics) {
  MedianInterval five = median_interval({1, 2, 3, 4, 5});
  EXPECT_FALSE(five.defined);
  MedianInterval six = median_interval({10, 9, 11, 12, 8, 10});
  ASSERT_TRUE(six.defined);
  EXPECT_DOUBLE_EQ(six.low, 8);
  EXPECT_DOUBLE_EQ(six.high, 12);
  EXPECT_DOUBLE_EQ(six.median, 10);
  EXPECT_NEAR(six.coverage, 1.0 - 2.0 / 64.0, 1e-12);
  EXPECT_DOUBLE_EQ(six.half_width_percent, 20.0);
  MedianInterval nine = median_interval({1, 2, 3, 4, 5, 6, 7, 8, 9});
  ASSERT_TRUE(nine.defined);
  EXPECT_DOUBLE_EQ(nine.low, 2);
  EXPECT_DOUBLE_EQ(nine.high, 8);
  EXPECT_NEAR(nine.coverage, 1.0 - 2.0 * 10.0 / 512.0, 1e-12);
  // Large n stays finite (log-space binomial) and the interval narrows around the median.
  std::vector<double> many;
  for (int i = 0; i < 1001; ++i) many.push_back(100.0 + (i % 11) * 0.1);
  MedianInterval big = median_interval(many);
  ASSERT_TRUE(big.defined);
  EXPECT_LE(big.half_width_percent, 0.11);
  EXPECT_GE(big.coverage, 0.95);
}

TEST(RepetitionPolicy, StopsOnCountPrecisionCapOrTime) {
  RepetitionPolicy fixed;
  fixed.repetitions = 3;
  EXPECT_TRUE(needs_repetition(fixed, {1, 1}, 0));
  EXPECT_FALSE(needs_repetition(fixed, {1, 1, 1}, 0));

  RepetitionPolicy precise;
  precise.precision_percent = 2.0;
  precise.max_repetitions = 8;
  EXPECT_TRUE(needs_repetition(precise, {1, 1, 1, 1, 1}, 0));            // below the 6 an interval needs
  EXPECT_FALSE(needs_repetition(precise, {1, 1, 1.01, 1, 0.99, 1}, 0));  // +-1%
  EXPECT_TRUE(needs_repetition(precise, {1, 1, 1.1, 1, 0.9, 1}, 0));     // +-10%: another
  EXPECT_FALSE(needs_repetition(precise, {1, 1, 1.1, 1, 0.9, 1, 1.2, 0.8}, 0));  // the cap
  EXPECT_EQ(precise.cap(), 8);

  RepetitionPolicy sustain;
  sustain.sustain_seconds = 10;
  EXPECT_TRUE(needs_repetition(sustain, {1, 1, 1, 1, 1, 1, 1, 1, 1, 1}, 9.9));
  EXPECT_FALSE(needs_repetition(sustain, {1}, 10.0));
  EXPECT_TRUE(needs_repetition(sustain, {}, 20.0));  // every case gets at least one repetition
}

// A precise case must still have enough repetitions for `omnishadow compare` over the run's cases to flag it.
TEST(RepetitionPolicy, PrecisionMinimumLetsTheComparisonResolve) {
  RepetitionPolicy precise;
  precise.precision_percent = 2.0;
  EXPECT_EQ(precise.minimum(),
            RepetitionPolicy::kMinForInterval);  // one case: 4 would do, the interval needs 6
  precise.compared_cases = 24;
  EXPECT_EQ(precise.minimum(), 7);
  const std::vector<double> quiet{1, 1, 1.001, 1, 0.999, 1};  // +-0.1% after 6
  EXPECT_TRUE(needs_repetition(precise, quiet, 0));
  std::vector<double> seven = quiet;
  seven.push_back(1.0);
  EXPECT_FALSE(needs_repetition(precise, seven, 0));
  precise.compared_cases = 96;
  EXPECT_EQ(precise.minimum(), 8);
  precise.repetitions = 12;
  EXPECT_EQ(precise.minimum(), 12);  // a larger fixed count stays the minimum

  RepetitionPolicy fixed;  // a fixed count is the user's choice, resolvable or not (compare says which)
  fixed.repetitions = 3;
  fixed.compared_cases = 24;
  EXPECT_EQ(fixed.minimum(), 3);
}

TEST(RepetitionPolicy, StabilityIsBestOverWorst) {
  EXPECT_DOUBLE_EQ(stability_percent({10, 10.5, 12.5}), 80.0);
  EXPECT_DOUBLE_EQ(stability_percent({7}), 100.0);
}

}  // namespace
}  // namespace omnishadow::bench
