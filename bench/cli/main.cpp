// omnishadow: benchmark and profiling harness for omnidirectional (cube-map) shadow mapping.
// `omnishadow list` shows what this machine can run; `omnishadow run ...` runs a matrix. See README.md.
// The options are declared in bench/cli/cli_options.cpp; this file only splits the arguments and dispatches.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/cli/case_isolation.h"
#include "bench/cli/cli_options.h"
#include "bench/cli/commands.h"
#include "bench/report/compare.h"
#include "bench/report/merge.h"
#include "bench/report/results_store.h"
#include "bench/run/system_info.h"

using namespace omnishadow;
using namespace omnishadow::bench;

namespace {

// False, said in one line, when --scenes-dir names no folder (list and run read it).
bool scenes_dir_exists(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::is_directory(dir, ec)) return true;
  print_error("--scenes-dir " + dir + ": no such folder (it holds the bundled <scene>.json files)");
  return false;
}

// compare, merge and device-key read results files only.
int run_file_command(CLI::App* cmp, CLI::App* mrg, const CompareFlags& cf, CompareOptions compare,
                     const std::string& merge_out, const std::vector<std::string>& merge_inputs,
                     const std::string& key_run) {
  try {
    if (cmp->parsed()) {
      if (!cf.gate.empty()) apply_gate_file(cf.gate, compare);
      compare.timing = !cf.no_timing;
      compare.timing_fails = !cf.timing_report_only;
      return compare_command(cf.base_run, cf.new_run, compare);
    }
    if (mrg->parsed()) {
      const MergeResult merged = merge_runs(merge_out, merge_inputs);
      std::cout << "merged " << merge_inputs.size() << " runs into " << merge_out << "/results.json\n";
      if (merged.complete) return 0;
      // Written, but not a whole run: said first thing on stderr, and the exit status says so too.
      print_error("merge: INCOMPLETE: " + merged.describe() +
                  "; the merged run says complete: false, and compare counts the cases it lacks as missing");
      return 1;
    }
    for (const auto& [backend, device] : device_keys(load_run(key_run))) std::cout << device << "\n";
    return 0;
  } catch (const std::exception& e) {
    print_error(e.what());
    return 2;
  }
}

struct FileArgs {
  ReportArgs report;
  HistoryArgs history, alerts;
  AcceptArgs accept{kDefaultStoreUrl, {}};
  ThresholdArgs threshold{kDefaultStoreUrl, {".*", "", {}, {}, {}}};
  std::vector<std::string> runs;
  std::string db = kDefaultStoreUrl;
  std::string fetch_db = kDefaultStoreUrl, fetch_out;
  FetchFilter fetch_filter;
  std::string export_run, export_format, export_out;
};
CLI::App* add_report_command(CLI::App& app, FileArgs& a) {
  CLI::App* rep = app.add_subcommand("report", "one self-contained HTML page of a run (and its history)");
  rep->add_option("run", a.report.run, "run folder")->required();
  rep->add_option("--history", a.report.history,
                  "run folders (or folders of runs) of the same device, any order");
  rep->add_option("--db", a.report.db,
                  "the history from the results store too: sqlite:PATH or postgresql://...");
  rep->add_option("--out", a.report.out, "the HTML file (default RUN/report.html)");
  return rep;
}
CLI::App* add_history_command(CLI::App& app, FileArgs& a) {
  CLI::App* his = app.add_subcommand("history", "change points over many runs of one device, and alerts");
  his->add_option("runs", a.history.runs, "run folders or folders of runs, any order");
  his->add_option("--db", a.history.db, "the runs of the results store too: sqlite:PATH or postgresql://...");
  his->add_option("--out", a.history.out, "folder for history.json and history.md (default: .)");
  his->add_option("--device-key", a.history.device_key,
                  "the device to follow, as history.md names it (default: the one with most runs)");
  his->add_option("--accepted", a.history.accepted, "accepted steps (default results/accepted_steps.json)");
  return his;
}
// alerts, accept and threshold: what changed and is not yet accepted, and the store's rules for it.
void add_alert_commands(CLI::App& app, FileArgs& a) {
  CLI::App* ale = app.add_subcommand("alerts", "what changed in the store's runs and is not yet accepted");
  a.alerts.db = kDefaultStoreUrl;
  ale->add_option("--db", a.alerts.db, "sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE")
      ->capture_default_str();
  ale->add_option("--out", a.alerts.out, "folder for alerts.json and alerts.md (default: .)");
  ale->add_option("--device-key", a.alerts.device_key,
                  "the device to follow, as the alerts name it (default: the one with most runs)");
  CLI::App* acc = app.add_subcommand("accept", "keep a step in the store as meant: it stops alerting");
  acc->add_option("--db", a.accept.db, "sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE")
      ->capture_default_str();
  acc->add_option("--case", a.accept.step.case_pattern, "the cases (a regular expression, searched)")
      ->required();
  acc->add_option("--metric", a.accept.step.metric_pattern, "the metrics (a regular expression)")->required();
  acc->add_option("--commit", a.accept.step.commit, "the first commit after the step (or a prefix)")
      ->required();
  acc->add_option("--reason", a.accept.step.reason, "why it is meant")->required();
  CLI::App* thr = app.add_subcommand("threshold", "keep in the store what counts as a step for a metric");
  thr->add_option("--db", a.threshold.db, "sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE")
      ->capture_default_str();
  thr->add_option("--metric", a.threshold.threshold.metric, "the metrics (a regular expression)")->required();
  thr->add_option("--device", a.threshold.threshold.device, "the devices (a regular expression)")
      ->capture_default_str();
  thr->add_option("--percent", a.threshold.threshold.percent, "a fixed step, in percent")
      ->check(finite_in(1e-9, 1e9));
  thr->add_option("--alpha", a.threshold.threshold.alpha, "the timing test's alpha")
      ->check(finite_in(1e-12, 1.0));
  thr->add_option("--min-effect", a.threshold.threshold.min_effect, "the smallest step, as a fraction (0.05)")
      ->check(finite_in(0.0, 1e9));
}
CLI::App* add_store_command(CLI::App& app, FileArgs& a) {
  CLI::App* sto = app.add_subcommand("store", "put runs into a database: an SQLite file or PostgreSQL");
  sto->add_option("runs", a.runs, "run folders or results.json files")->required();
  sto->add_option("--db", a.db, "sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE")->capture_default_str();
  CLI::App* fet = app.add_subcommand("fetch", "stored runs back out of the database, as run folders");
  fet->add_option("--db", a.fetch_db, "sqlite:PATH or postgresql://USER@HOST:PORT/DATABASE")
      ->capture_default_str();
  fet->add_option("--out", a.fetch_out, "a new (or empty) folder for the runs")->required();
  fet->add_option("--device-key", a.fetch_filter.device_key,
                  "only runs with this device (omnishadow device-key)");
  fet->add_option("--commit", a.fetch_filter.commit, "only runs of this commit (a prefix will do)");
  return sto;
}
CLI::App* add_export_command(CLI::App& app, FileArgs& a) {
  CLI::App* exp =
      app.add_subcommand("export", "a run in a dashboard's format: Bencher or github-action-benchmark");
  exp->add_option("run", a.export_run, "run folder or results.json")->required();
  exp->add_option("--format", a.export_format, "bencher or github-action-benchmark")->required();
  exp->add_option("--out", a.export_out, "the JSON file (default: stdout)");
  return exp;
}
// report, history, store, fetch and export: -1 when none of them was asked for.
int run_store_or_page_command(CLI::App& app, const FileArgs& a) {
  if (app.got_subcommand("report")) return report_command(a.report);
  if (app.got_subcommand("history")) return history_command(a.history);
  if (app.got_subcommand("alerts")) return history_command(a.alerts, true);
  if (app.got_subcommand("accept")) return accept_command(a.accept);
  if (app.got_subcommand("threshold")) return threshold_command(a.threshold);
  if (app.got_subcommand("store")) return store_command(a.runs, a.db);
  if (app.got_subcommand("fetch")) return fetch_command(a.fetch_db, a.fetch_out, a.fetch_filter);
  if (app.got_subcommand("export")) return export_command(a.export_run, a.export_format, a.export_out);
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  // Google Benchmark's flags go to Google Benchmark; everything else is ours.
  RunCommand run;
  std::vector<std::string> ours;
  run.command_line = argv[0];
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    run.args.push_back(a);
    if (a.rfind("--benchmark_", 0) == 0) {
      run.benchmark_args.push_back(a);
      run.command_line += " " + a;
      continue;
    }
    ours.push_back(a);
    if (is_worker_argument(a)) {  // the supervisor's to its worker: not part of the run's command line
      if (i + 1 < argc) run.args.push_back(argv[i + 1]), ours.push_back(argv[i + 1]), ++i;
      continue;
    }
    run.command_line += " " + a;
  }

  CLI::App app{"omnishadow: benchmark harness for point-light (cube-map) shadow mapping"};
  app.require_subcommand(1);
  // The commit the binary was built from, as every results file records it (cmake/build_commit.cmake).
  app.set_version_flag("--version", [] {
    const std::string date = build_commit_date();
    return "omnishadow " + build_commit() + (date.empty() ? "" : " (" + date + ")");
  });
  CommonOptions common;
  common.scenes_dir = project_path("scenes");
  CLI::App* list =
      app.add_subcommand("list", "backends, scenes, techniques, filters and what this machine supports");
  add_common_options(*list, common);
  RunFlags run_flags;
  CLI::App* r =
      app.add_subcommand("run", "run a benchmark matrix (Google Benchmark --benchmark_* flags apply)");
  add_common_options(*r, common);
  add_run_options(*r, run, run_flags);
  CompareOptions compare;
  CompareFlags compare_flags;
  add_compare_options(
      *app.add_subcommand("compare", "compare two runs: timing (U-test), work counters, images"), compare,
      compare_flags);
  std::string merge_out, key_run;
  std::vector<std::string> merge_inputs;
  CLI::App* mrg = app.add_subcommand("merge", "join the results of --shard runs into one run");
  mrg->add_option("out", merge_out, "folder for the merged results.json")->required();
  mrg->add_option("runs", merge_inputs, "run folders or results.json files")->required();
  FileArgs files;  // report, history, store, fetch and export, in functions of their own: main() stays short
  add_report_command(app, files);
  add_history_command(app, files);
  add_alert_commands(app, files);
  add_store_command(app, files);
  add_export_command(app, files);
  CLI::App* key =
      app.add_subcommand("device-key", "print the device key of each backend of a run (baselines/)");
  key->add_option("run", key_run, "run folder or results.json")->required();

  try {
    std::vector<std::string> reversed(ours.rbegin(), ours.rend());  // CLI11 parses a reversed vector
    app.parse(reversed);
    if (!r->parsed() && !run.benchmark_args.empty())
      throw std::invalid_argument(run.benchmark_args.front() + " applies to 'run' only");
    if (r->parsed()) finish_run_options(run, run_flags, common);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version: printed, exit 0
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error(parse_error_message(app, e, ours));
    return 2;
  } catch (const std::invalid_argument& e) {  // a list option's parser, or finish_run_options
    print_error(e.what());
    return 2;
  }
  if ((list->parsed() || r->parsed()) && !scenes_dir_exists(common.scenes_dir)) return 2;
  if (list->parsed()) return list_command(common.scenes_dir, common.backend_options());
  if (r->parsed()) return run_command(run);
  if (const int code = run_store_or_page_command(app, files); code >= 0) return code;
  return run_file_command(app.get_subcommand("compare"), mrg, compare_flags, compare, merge_out, merge_inputs,
                          key_run);
}
