#include "bench/run/device_state.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;

std::string read_line(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  return line;
}

double read_number(const fs::path& p, double scale) {
  std::string line = read_line(p);
  if (line.empty()) return -1.0;
  try {
    return std::stod(line) * scale;
  } catch (const std::exception&) {
    return -1.0;
  }
}

// NVML, declared here rather than from nvml.h so that the build needs no NVIDIA package.
class NvmlProbe final : public DeviceStateProbe {
 public:
  using Device = void*;
  static std::unique_ptr<NvmlProbe> open(const std::string& renderer) {
    void* lib = dlopen("libnvidia-ml.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!lib) return nullptr;
    auto probe = std::unique_ptr<NvmlProbe>(new NvmlProbe(lib));
    if (!probe->bind() || probe->init_() != 0 || !probe->pick(renderer)) return nullptr;
    return probe;
  }
  ~NvmlProbe() override {
    if (locked_ && reset_locked_) reset_locked_(device_);
    if (shutdown_) shutdown_();
    dlclose(lib_);
  }
  std::string source() const override { return "nvml"; }
  DeviceState sample() override {
    DeviceState s;
    unsigned v = 0;
    if (clock_(device_, 0 /* NVML_CLOCK_GRAPHICS */, &v) == 0) s.clock_mhz = v;
    if (clock_(device_, 2 /* NVML_CLOCK_MEM */, &v) == 0) s.memory_clock_mhz = v;
    if (temperature_(device_, 0 /* NVML_TEMPERATURE_GPU */, &v) == 0) s.temperature_c = v;
    if (power_(device_, &v) == 0) s.power_w = v * 1e-3;  // milliwatts
    unsigned long long reasons = 0;
    if (throttle_ && throttle_(device_, &reasons) == 0) s.throttle = throttle_words(reasons);
    return s;
  }
  // Locks the graphics clock at the device's default applications clock: a clock it sustains under load,
  // where boost would wander with temperature and power. Needs root (or the driver's permission for this
  // user).
  std::string lock_clocks() override {
    if (!set_locked_ || !reset_locked_) return "this NVML has no nvmlDeviceSetGpuLockedClocks";
    unsigned mhz = 0;
    if (!default_clock_ || default_clock_(device_, 0 /* NVML_CLOCK_GRAPHICS */, &mhz) != 0 || mhz == 0)
      return "NVML reports no default applications clock to lock at";
    switch (int rc = set_locked_(device_, mhz, mhz)) {
      case 0:
        locked_ = true;
        std::fprintf(stderr,
                     "[lock-clocks] graphics clock locked at %u MHz (NVML; reset when the run ends)\n", mhz);
        return "";
      case 4:
        return "NVML: no permission to lock clocks (run as root, or lock them with nvidia-smi "
               "--lock-gpu-clocks)";
      case 3:
        return "NVML: locking clocks is not supported on this GPU";
      default:
        return "NVML error " + std::to_string(rc) + " locking clocks at " + std::to_string(mhz) + " MHz";
    }
  }

 private:
  explicit NvmlProbe(void* lib) : lib_(lib) {}
  template <typename F>
  bool get(F& f, const char* name) {
    f = reinterpret_cast<F>(dlsym(lib_, name));
    return f != nullptr;
  }
  bool bind() {
    get(throttle_, "nvmlDeviceGetCurrentClocksThrottleReasons");  // optional
    get(shutdown_, "nvmlShutdown");
    get(set_locked_, "nvmlDeviceSetGpuLockedClocks");  // optional: --lock-clocks
    get(reset_locked_, "nvmlDeviceResetGpuLockedClocks");
    get(default_clock_, "nvmlDeviceGetDefaultApplicationsClock");
    return get(init_, "nvmlInit_v2") && get(count_, "nvmlDeviceGetCount_v2") &&
           get(handle_, "nvmlDeviceGetHandleByIndex_v2") && get(name_, "nvmlDeviceGetName") &&
           get(clock_, "nvmlDeviceGetClockInfo") && get(temperature_, "nvmlDeviceGetTemperature") &&
           get(power_, "nvmlDeviceGetPowerUsage");
  }
  // The NVML device whose name the API's renderer string contains; the first one otherwise.
  bool pick(const std::string& renderer) {
    unsigned count = 0;
    if (count_(&count) != 0 || count == 0) return false;
    handle_(0, &device_);
    for (unsigned i = 0; i < count; ++i) {
      Device d = nullptr;
      char name[96] = {};
      if (handle_(i, &d) == 0 && name_(d, name, sizeof name) == 0 &&
          renderer.find(name) != std::string::npos) {
        device_ = d;
        break;
      }
    }
    return device_ != nullptr;
  }
  static std::string throttle_words(unsigned long long r) {
    static const std::pair<unsigned long long, const char*> kReasons[] = {
        {0x2, "applications_clocks"}, {0x4, "sw_power_cap"},         {0x8, "hw_slowdown"},
        {0x10, "sync_boost"},         {0x20, "sw_thermal_slowdown"}, {0x40, "hw_thermal_slowdown"},
        {0x80, "hw_power_brake"}};  // 0x1 (GPU idle) is not a throttle while a case runs
    std::string out;
    for (const auto& [bit, word] : kReasons)
      if (r & bit) out += (out.empty() ? "" : " ") + std::string(word);
    return out;
  }

  void* lib_;
  Device device_ = nullptr;
  int (*init_)() = nullptr;
  int (*shutdown_)() = nullptr;
  int (*count_)(unsigned*) = nullptr;
  int (*handle_)(unsigned, Device*) = nullptr;
  int (*name_)(Device, char*, unsigned) = nullptr;
  int (*clock_)(Device, int, unsigned*) = nullptr;
  int (*temperature_)(Device, int, unsigned*) = nullptr;
  int (*power_)(Device, unsigned*) = nullptr;
  int (*throttle_)(Device, unsigned long long*) = nullptr;
  int (*set_locked_)(Device, unsigned, unsigned) = nullptr;
  int (*reset_locked_)(Device) = nullptr;
  int (*default_clock_)(Device, int, unsigned*) = nullptr;
  bool locked_ = false;
};

// AMD and Intel publish their state in sysfs under the DRM card whose PCI vendor matches.
class SysfsProbe final : public DeviceStateProbe {
 public:
  SysfsProbe(fs::path card, bool amd) : card_(std::move(card)), amd_(amd) {}
  static std::unique_ptr<SysfsProbe> find(const std::string& vendor_id) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator("/sys/class/drm", ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("card", 0) != 0 || name.find('-') != std::string::npos) continue;
      if (read_line(entry.path() / "device" / "vendor") == vendor_id)
        return std::make_unique<SysfsProbe>(entry.path(), vendor_id == "0x1002");
    }
    return nullptr;
  }
  std::string source() const override { return amd_ ? "amdgpu sysfs" : "i915 sysfs"; }
  DeviceState sample() override {
    DeviceState s;
    if (!amd_) {
      s.clock_mhz = read_number(card_ / "gt_cur_freq_mhz", 1.0);
      return s;
    }
    s.clock_mhz = current_level(card_ / "device" / "pp_dpm_sclk");
    s.memory_clock_mhz = current_level(card_ / "device" / "pp_dpm_mclk");
    std::error_code ec;
    for (const auto& hw : fs::directory_iterator(card_ / "device" / "hwmon", ec)) {
      s.temperature_c = read_number(hw.path() / "temp1_input", 1e-3);  // millidegrees
      s.power_w = read_number(hw.path() / "power1_average", 1e-6);     // microwatts
    }
    return s;
  }

 private:
  // pp_dpm_* lists the levels, "1: 1000Mhz *" marking the current one.
  static double current_level(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    while (std::getline(in, line))
      if (line.find('*') != std::string::npos) {
        size_t colon = line.find(':');
        try {
          return std::stod(line.substr(colon + 1));
        } catch (const std::exception&) {
          return -1.0;
        }
      }
    return -1.0;
  }
  fs::path card_;
  bool amd_;
};

// CPU drivers render on the CPUs: their frequency is the clock that matters.
class CpuFrequencyProbe final : public DeviceStateProbe {
 public:
  std::string source() const override { return "cpu frequency"; }
  DeviceState sample() override {
    DeviceState s;
    double sum = 0;
    int n = 0;
    std::error_code ec;
    for (const auto& cpu : fs::directory_iterator("/sys/devices/system/cpu", ec)) {
      double khz = read_number(cpu.path() / "cpufreq" / "scaling_cur_freq", 1e-3);
      if (khz > 0) sum += khz, ++n;
    }
    if (n == 0) {  // no cpufreq (containers, VMs): the kernel's per-CPU figure
      std::ifstream in("/proc/cpuinfo");
      std::string line;
      while (std::getline(in, line))
        if (line.rfind("cpu MHz", 0) == 0) try {
            sum += std::stod(line.substr(line.find(':') + 1)), ++n;
          } catch (const std::exception&) {
          }
    }
    if (n > 0) s.clock_mhz = sum / n;
    s.governor = read_line("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor");
    return s;
  }
};

}  // namespace

nlohmann::json to_json(const DeviceState& s) {
  nlohmann::json j = nlohmann::json::object();
  auto put = [&](const char* key, double v) {
    if (v >= 0) j[key] = v;
  };
  put("clock_mhz", s.clock_mhz);
  put("memory_clock_mhz", s.memory_clock_mhz);
  put("temperature_c", s.temperature_c);
  put("power_w", s.power_w);
  if (!s.throttle.empty()) j["throttle"] = s.throttle;
  if (!s.governor.empty()) j["governor"] = s.governor;
  return j;
}

std::unique_ptr<DeviceStateProbe> make_device_state_probe(const DeviceInfo& device) {
  if (!device.shares_host_memory) {
    const std::string& r = device.renderer;
    const bool nvidia = r.find("NVIDIA") != std::string::npos || device.vendor == "0x10de";
    if (nvidia)
      if (auto p = NvmlProbe::open(r)) return p;
    if (r.find("AMD") != std::string::npos || r.find("Radeon") != std::string::npos ||
        device.vendor == "0x1002")
      if (auto p = SysfsProbe::find("0x1002")) return p;
    if (r.find("Intel") != std::string::npos || device.vendor == "0x8086")
      if (auto p = SysfsProbe::find("0x8086")) return p;
  }
  return std::make_unique<CpuFrequencyProbe>();
}

std::string clock_warning(const std::vector<DeviceState>& samples, double tolerance) {
  double lo = 0, hi = 0;
  int moved = 0, repetitions = 0;
  std::string throttle;
  for (size_t i = 0; i + 1 < samples.size(); i += 2) {
    const DeviceState &before = samples[i], &after = samples[i + 1];
    ++repetitions;
    for (const DeviceState* s : {&before, &after})
      if (!s->throttle.empty() && throttle.empty()) throttle = s->throttle;
    if (before.clock_mhz <= 0 || after.clock_mhz <= 0) continue;
    const double a = std::min(before.clock_mhz, after.clock_mhz),
                 b = std::max(before.clock_mhz, after.clock_mhz);
    if (b - a <= tolerance * b) continue;
    ++moved;
    lo = lo == 0 ? a : std::min(lo, a);
    hi = std::max(hi, b);
  }
  char buf[160] = "";
  if (moved > 0)
    std::snprintf(buf, sizeof buf, "clocks moved inside %d of %d timed repetitions: %.0f-%.0f MHz", moved,
                  repetitions, lo, hi);
  std::string out = buf;
  if (!throttle.empty()) out += (out.empty() ? "" : "; ") + std::string("throttled: ") + throttle;
  return out;
}

bool clock_steady(const std::vector<ClockReading>& readings, double window_s, double tolerance) {
  if (readings.empty() || readings.back().seconds - readings.front().seconds < window_s) return false;
  const double from = readings.back().seconds - window_s;
  double lo = readings.back().mhz, hi = readings.back().mhz;
  // Back to the last reading at or before the window's start, so that the readings cover all of it.
  for (size_t i = readings.size(); i-- > 0;) {
    if (readings[i].mhz <= 0) return false;
    lo = std::min(lo, readings[i].mhz);
    hi = std::max(hi, readings[i].mhz);
    if (readings[i].seconds <= from) break;
  }
  return hi - lo <= tolerance * hi;
}

std::string clock_range(const std::vector<DeviceState>& samples) {
  auto range = [&](double DeviceState::*field, const char* unit) -> std::string {
    double lo = 0, hi = 0;
    for (const DeviceState& s : samples) {
      if (s.*field <= 0) continue;
      lo = lo == 0 ? s.*field : std::min(lo, s.*field);
      hi = std::max(hi, s.*field);
    }
    if (hi <= 0) return "";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.0f-%.0f %s", lo, hi, unit);
    return buf;
  };
  std::string out = range(&DeviceState::clock_mhz, "MHz");
  if (std::string t = range(&DeviceState::temperature_c, "C"); !t.empty())
    out += (out.empty() ? "" : ", ") + t;
  return out.empty() ? "-" : out;
}

}  // namespace omnishadow::bench
