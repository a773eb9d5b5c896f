#pragma once
// The subcommands of the omnishadow CLI. Each returns the process exit code:
// 0 success, 1 a check failed (run --check), 2 usage or input error.

#include <map>
#include <string>
#include <vector>

#include "bench/matrix.h"

namespace omnishadow::bench {

struct RunCommand {
  MatrixSpec matrix;
  std::string out_dir;
  std::string scenes_dir;
  int warmup_frames = 2;
  int frames = 10;
  int check_frame = 0;
  double face_tolerance = 0.0;
  double lit_tolerance = 0.0;
  double cross_lit_tolerance = 2.0;
  double cross_shadow_tolerance = 0.1;
  double cross_max_percent = 0.1;
  bool write_images = true;
  bool accuracy = true;
  bool memory_precheck = true;
  bool stability = false;
  double max_error_percent = -1.0;
  float light_radius = 0.1f;
  int light_samples_per_axis = 8;
  bool check = false;          // exit 1 if any case failed or failed its checks
  int injected_work = 0;       // --inject-fragment-work
  int shard_index = 0;
  int shard_count = 1;
  std::map<std::string, std::string> backend_options;
  std::vector<std::string> benchmark_args;  // --benchmark_* flags, passed to Google Benchmark
  std::string command_line;
};

int run_command(const RunCommand& cmd);
int list_command(const std::string& scenes_dir, const std::map<std::string, std::string>& backend_options);

// One line on stderr, "omnishadow: error: ...".
void print_error(const std::string& message);

}  // namespace omnishadow::bench
