#pragma once
// The command line, declared once: each option is bound straight to the structure that uses it (MatrixSpec,
// RunOptions, RunCommand, CompareOptions), with that structure's default as its default. main() only
// dispatches.

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "bench/cli/commands.h"
#include "bench/report/compare.h"

namespace omnishadow::bench {

// Options every subcommand that brings up a backend takes.
struct CommonOptions {
  std::string scenes_dir;
  std::string egl_platform = "surfaceless";
  std::string gl_device = "0";
  std::string gl_profile = "auto";
  std::string vk_device;
  bool api_checks = false;
  std::map<std::string, std::string> backend_options() const;  // create_backend's options
};
// A real-valued option's check: a finite number from lo to hi (CLI::Range lets NaN and "inf" through).
CLI::Validator finite_in(double lo, double hi);

void add_common_options(CLI::App& sub, CommonOptions& o);

// `run`: the matrix axes, the harness options and the command's own. Flags that are the negation of a default
// (--no-accuracy, ...) land in RunFlags and are applied by finish_run_options.
struct RunFlags {
  std::string images = "failed";
  std::string cube_read_back = "auto";
  bool no_images = false;
  bool no_accuracy = false;
  bool no_timing = false;  // run's --no-timing (compare's has its own)
  bool no_memory_precheck = false;
  std::string shard;
};
void add_run_options(CLI::App& sub, RunCommand& run, RunFlags& flags);
// Two of its groups (isolation_and_experiment_options.cpp): a crashing driver's containment and captures, and
// the options that test the harness itself (injected faults and work, replicas, perturbations, emulations).
void add_isolation_options(CLI::App& r, RunCommand& run);
void add_experiment_options(CLI::App& r, RunCommand& run);
// Applies the flags and checks what CLI11 cannot (shard syntax, --benchmark_out); throws
// std::invalid_argument.
void finish_run_options(RunCommand& run, const RunFlags& flags, const CommonOptions& common);

struct CompareFlags {
  std::string base_run, new_run;
  std::string gate;  // --gate FILE
  bool no_timing = false;
  bool timing_report_only = false;
};
void add_compare_options(CLI::App& sub, CompareOptions& compare, CompareFlags& flags);

// CLI11's parse errors as a user reads them: a command that is missing or unknown is named with the commands
// there are; an option given twice says so (a list option takes one comma list). Others pass through.
// `args`: the command line's own arguments, in order.
std::string parse_error_message(const CLI::App& app, const CLI::ParseError& e,
                                const std::vector<std::string>& args);

}  // namespace omnishadow::bench
