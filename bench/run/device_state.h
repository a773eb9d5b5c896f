#pragma once
// The device's state around each case's timed repetitions, wherever the platform tells: clocks, temperature,
// power and throttle reasons. A GPU idles at a fraction of its boost clock (an H100: 345 against 1980 MHz),
// so a figure measured while the clock moved is not the device's figure; the summary warns about such cases.
//   NVIDIA: NVML (libnvidia-ml.so.1, opened at run time: no build dependency, nothing needed where it is
//   absent) AMD:    sysfs of the amdgpu card (pp_dpm_sclk / pp_dpm_mclk, hwmon temperature and power) Intel:
//   sysfs of the i915 card (gt_cur_freq_mhz) CPU drivers (llvmpipe, lavapipe) and anything else: the CPUs'
//   current frequency (cpufreq, or /proc/cpuinfo) and the cpufreq governor.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "backends/backend.h"

namespace omnishadow::bench {

struct DeviceState {
  double clock_mhz = -1.0;  // graphics (shader) clock; CPU drivers: the mean CPU frequency
  double memory_clock_mhz = -1.0;
  double temperature_c = -1.0;
  double power_w = -1.0;
  std::string throttle;  // NVML's active clock event reasons as words ("sw_power_cap hw_slowdown"); "" none
  std::string governor;  // cpufreq governor where the clock is a CPU's
};
nlohmann::json to_json(const DeviceState& s);  // fields that are unknown (-1, "") are left out

class DeviceStateProbe {
 public:
  virtual ~DeviceStateProbe() = default;
  virtual std::string source() const = 0;  // "nvml", "amdgpu sysfs", "i915 sysfs", "cpu frequency", "none"
  virtual DeviceState sample() = 0;
  // `run --lock-clocks`: fixes the graphics clock for the rest of the run (restored when the probe is
  // destroyed: at exit, and after SIGINT/SIGTERM, which end the run normally). "" once locked; otherwise why
  // not, one line.
  virtual std::string lock_clocks() {
    return "the harness can lock clocks only through NVIDIA's NVML; the clock source here is " + source() +
           " (lock them with the platform's tools: docs/guide.md, \"Stable numbers on a GPU\")";
  }
};
// The best source for this device (by vendor and renderer), falling back to the CPU frequency.
std::unique_ptr<DeviceStateProbe> make_device_state_probe(const DeviceInfo& device);

// `samples` are a case's device states in pairs, before and after each timed repetition (gbench_glue.cpp).
// "clocks moved inside 2 of 8 timed repetitions: 345-1980 MHz": a repetition whose clock at its end differs
// from its start by more than `tolerance` (relative to the higher), or throttling seen in one; empty when
// every repetition ran at one clock or the clock is unknown. A clock that differs between repetitions is
// recorded (each sample is in results.json) but is no warning: each figure was measured at one clock.
std::string clock_warning(const std::vector<DeviceState>& samples, double tolerance = 0.05);

// One clock reading `seconds` after rendering began.
struct ClockReading {
  double seconds = 0.0;
  double mhz = -1.0;
};
// Whether the clock held within `tolerance` of the highest reading over the last `window_s` seconds (the
// device has settled): false until the readings span the window. A span, not a count of readings: an H200
// read 345 MHz for the first 0.1 s of continuous rendering, and three readings 50 ms apart called that idle
// clock steady.
bool clock_steady(const std::vector<ClockReading>& readings, double window_s = 1.0, double tolerance = 0.02);
// "1410-1980 MHz, 41-63 C" over the samples (the parts known); "-" when nothing is.
std::string clock_range(const std::vector<DeviceState>& samples);

}  // namespace omnishadow::bench
