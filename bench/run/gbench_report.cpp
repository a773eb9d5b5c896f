#include "bench/run/gbench_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace omnishadow::bench {
namespace {

using Run = benchmark::BenchmarkReporter::Run;

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Sample standard deviation (n - 1), as Google Benchmark's StatisticsStdDev.
double stddev_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  double m = mean_of(v), ss = 0.0;
  for (double x : v) ss += (x - m) * (x - m);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

double cv_of(const std::vector<double>& v) {
  double m = mean_of(v);
  return m != 0.0 ? stddev_of(v) / m : 0.0;
}

}  // namespace

std::string explain_debug_library(const std::string& context_text) {
  std::string out;
  std::istringstream lines(context_text);
  for (std::string line; std::getline(lines, line);)
    out +=
        line.find(kDebugLibraryWarning) != std::string::npos ? std::string(kDebugLibraryNote) : line + "\n";
  return out;
}

bool RoundReporter::ReportContext(const Context& context) {
  if (context_printed_) return true;
  context_printed_ = true;
  // The base class prints the context to the error stream: captured, and passed on with the warning
  // explained.
  std::ostream& err = GetErrorStream();
  std::ostringstream captured;
  SetErrorStream(&captured);
  const bool ok = benchmark::ConsoleReporter::ReportContext(context);
  SetErrorStream(&err);
  err << explain_debug_library(captured.str());
  return ok;
}

void RoundReporter::ReportRuns(const std::vector<Run>& runs) {
  std::vector<Run> compact;
  for (Run run : runs) {
    if (run.error_occurred) continue;  // skipped after a stop request: never timed, never a repetition
    run.run_name.repetitions.clear();  // the name stays the case's, whatever the round
    std::vector<Run>& kept = runs_[run.benchmark_name()];
    if (kept.empty()) order_.push_back(run.benchmark_name());
    run.repetition_index = static_cast<int64_t>(kept.size());
    kept.push_back(run);
    // Console: only the headline counters; the JSON keeps all of them.
    std::erase_if(run.counters, [](const auto& kv) {
      return kv.first != "shadow_wall_ms" && kv.first != "lighting_wall_ms" && kv.first != "shadow_gpu_ms";
    });
    compact.push_back(run);
  }
  benchmark::ConsoleReporter::ReportRuns(compact);
}

std::vector<Run> RoundReporter::all_runs() const {
  std::vector<Run> out;
  for (const std::string& name : order_) {
    std::vector<Run> runs = runs_.at(name);
    for (Run& r : runs) r.repetitions = static_cast<int64_t>(runs.size());
    out.insert(out.end(), runs.begin(), runs.end());
    if (runs.size() > 1) {
      std::vector<Run> aggregates = aggregate_runs(runs);
      out.insert(out.end(), aggregates.begin(), aggregates.end());
    }
  }
  return out;
}

std::vector<Run> aggregate_runs(const std::vector<Run>& runs) {
  std::vector<Run> ok;
  for (const Run& r : runs)
    if (!r.error_occurred) ok.push_back(r);
  if (ok.size() < 2) return {};
  std::vector<double> real, cpu;
  std::map<std::string, std::vector<double>> counters;
  for (const Run& r : ok) {
    real.push_back(r.GetAdjustedRealTime());
    cpu.push_back(r.GetAdjustedCPUTime());
    for (const auto& [name, c] : r.counters) counters[name].push_back(c.value);
  }
  struct Stat {
    const char* name;
    double (*compute)(const std::vector<double>&);
    benchmark::StatisticUnit unit;
  };
  const Stat stats[] = {
      {"mean", mean_of, benchmark::kTime},
      {"median", [](const std::vector<double>& v) { return median_of(v); }, benchmark::kTime},
      {"stddev", stddev_of, benchmark::kTime},
      {"cv", cv_of, benchmark::kPercentage}};
  const double n = static_cast<double>(ok.size());
  // GetAdjusted*Time() = accumulated * unit multiplier / iterations; a percentage is written as accumulated.
  const double to_accumulated = n / benchmark::GetTimeUnitMultiplier(ok.front().time_unit);
  std::vector<Run> out;
  for (const Stat& s : stats) {
    Run a = ok.front();
    a.run_type = Run::RT_Aggregate;
    a.aggregate_name = s.name;
    a.aggregate_unit = s.unit;
    a.repetition_index = Run::no_repetition_index;
    a.repetitions = static_cast<int64_t>(runs.size());
    a.iterations = static_cast<benchmark::IterationCount>(ok.size());
    const double scale = s.unit == benchmark::kTime ? to_accumulated : 1.0;
    a.real_accumulated_time = s.compute(real) * scale;
    a.cpu_accumulated_time = s.compute(cpu) * scale;
    a.counters.clear();
    for (const auto& [name, values] : counters) a.counters[name] = benchmark::Counter(s.compute(values));
    out.push_back(a);
  }
  return out;
}

void write_gbench_json(const std::string& path, const std::vector<Run>& runs) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw std::runtime_error(path + ": cannot write");
  benchmark::JSONReporter json;
  json.SetOutputStream(&file);
  json.SetErrorStream(&std::cerr);
  json.ReportContext(benchmark::BenchmarkReporter::Context());
  if (!runs.empty()) json.ReportRuns(runs);
  json.Finalize();
  file.close();
  if (!file) throw std::runtime_error(path + ": write failed");
}

}  // namespace omnishadow::bench
