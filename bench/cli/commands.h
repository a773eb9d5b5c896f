#pragma once
// The subcommands of the omnishadow CLI. Each returns the process exit code:
// 0 success, 1 a check failed (run --check), 2 usage or input error.

#include <map>
#include <string>
#include <vector>

#include "bench/report/results_store.h"
#include "bench/run/case_runner.h"
#include "bench/run/matrix.h"
#include "bench/run/repetition_policy.h"

namespace omnishadow::bench {

// A file or folder the project ships (the scenes, the report's scripts): beside an installed binary,
// <prefix>/share/omnishadow/<relative>, where <prefix> is the parent of the binary's folder (read from
// /proc/self/exe, so an installed tree can be moved anywhere); else in the source tree the build came from.
std::string project_path(const std::string& relative);

// A `run` request: the matrix, the harness's own options (bound by the CLI straight to RunOptions), and what
// only the command uses.
struct RunCommand {
  MatrixSpec matrix;
  RunOptions harness;  // out_dir empty: results/run-<time>
  bool check = false;  // exit 1 if any case failed or failed its checks
  int shard_index = 0;
  int shard_count = 1;
  RepetitionPolicy repetitions;  // --benchmark_repetitions, --precision, --max-repetitions, --sustain
  std::vector<std::string> benchmark_args;  // --benchmark_* flags, passed to Google Benchmark
  std::string command_line;                 // as given, less the worker's own arguments
  std::vector<std::string> args;  // every argument after the program's name ("run", then the options)
  // Crash isolation (bench/cli/case_isolation.h): on by default (--isolation process); a case making no
  // progress for case_timeout_s is a hang. A worker process has worker_skip >= 0: it skips that many cases of
  // the matrix, names its cases and steps on worker_progress_fd, and writes its results to worker_results
  // (empty: OUT's).
  bool isolate = true;
  double case_timeout_s = 300.0;
  int crash_retries = 1;  // --crash-retries: a case whose worker died by a signal runs again this many times
  int worker_skip = -1;
  int worker_progress_fd = -1;
  std::string worker_results;
  std::string capture = "none";       // --capture: failed, crashed, all or none (bench/cli/capture.h)
  double capture_max_mb = 1024.0;     // --capture-max-mb
  std::string capture_tool = "auto";  // --capture-tool
};

int run_command(const RunCommand& cmd);
int list_command(const std::string& scenes_dir, const std::map<std::string, std::string>& backend_options);

// `report RUN [--history ...] [--db URL] [--out FILE]`: scripts/analysis/report.py (the HTML page is written
// with matplotlib, in Python), run with Debian's /usr/bin/python3; the history from run folders, the results
// store, or both (bench/cli/analysis_commands.cpp). Exit 2 when either is missing.
struct ReportArgs {
  std::string run, out, db;
  std::vector<std::string> history;
};
int report_command(const ReportArgs& args);
// `history RUN_OR_FOLDER... | --db URL [--out DIR] [--device-key KEY] [--accepted FILE]`:
// scripts/analysis/history.py over run folders, the results store's runs, or both; its exit code (1: an
// alert).
struct HistoryArgs {
  std::vector<std::string> runs;
  std::string db, out, device_key, accepted;
};
// alerts_only (`alerts --db URL`): only what is not yet accepted, with the commit range of each step, as
// alerts.md and alerts.json.
int history_command(const HistoryArgs& args, bool alerts_only = false);

// `store RUN... [--db URL]`: each run into the database in a transaction of its own (bench/report/
// results_store.h), one line each on stdout; exit 2 at the first run that cannot be read or stored (the runs
// before it are stored whole, it and the ones after not at all).
int store_command(const std::vector<std::string>& runs, const std::string& db);
// `export RUN --format bencher|github-action-benchmark [--out FILE]` (bench/report/export.h): to stdout, or
// written atomically to FILE.
int export_command(const std::string& run, const std::string& format, const std::string& out);
// `fetch --db URL --out DIR [--device-key KEY] [--commit SHA]`: every stored run the filter lets through as a
// run folder under DIR, as fetch_into writes them; DIR must be new or empty.
int fetch_command(const std::string& db, const std::string& out, const FetchFilter& filter);
// Each stored run as DIR/NAME/results.json (the document as stored) and DIR/NAME/image_hashes.json (image
// path
// -> SHA-256, which history.py reads where the image itself is absent). NAME is the stored run's folder name,
// with its run key added where two share one. Throws StoreError.
struct FetchSummary {
  int runs = 0;
  int without_document = 0;  // runs stored under schema 1, not written
  int accepted_steps = 0,
      thresholds = 0;  // written beside the runs: DIR/accepted_steps.json, thresholds.json
};
// `accept --db URL --case RE --metric RE --commit SHA --reason TEXT`: a step judged meant, kept in the store.
struct AcceptArgs {
  std::string db;
  AcceptedStep step;
};
int accept_command(const AcceptArgs& args);
// `threshold --db URL --metric RE [--device RE] (--percent P | --alpha A --min-effect E)`.
struct ThresholdArgs {
  std::string db;
  Threshold threshold;
};
int threshold_command(const ThresholdArgs& args);
FetchSummary fetch_into(const std::string& db, const FetchFilter& filter, const std::string& dir);

// One line on stderr, "omnishadow: error: ...".
void print_error(const std::string& message);

}  // namespace omnishadow::bench
