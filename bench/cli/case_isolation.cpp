#include "bench/cli/case_isolation.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "bench/cli/commands.h"
#include "bench/cli/silence_watch.h"
#include "bench/io/file_io.h"
#include "bench/run/case_runner.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// SIGINT / SIGTERM to the supervisor: passed on to the worker, which stops after the repetition in hand,
// saves its results and exits 130 / 143, as a run without isolation does. A worker that ends otherwise after
// a stop was asked for (it crashed, or hung in the case in hand and was killed) gets no successor: the run
// stops there, with what finished, as the signal asked.
volatile std::sig_atomic_t g_signal_to_forward = 0;
volatile std::sig_atomic_t g_stop_signal = 0;  // the first SIGINT or SIGTERM
extern "C" void forward_later(int signal_number) {
  g_signal_to_forward = signal_number;
  if (g_stop_signal == 0) g_stop_signal = signal_number;
}

void pass_on_signal(pid_t worker) {
  if (const int s = g_signal_to_forward; s != 0) {
    g_signal_to_forward = 0;
    kill(worker, s);
  }
}

// What the worker said before it ended (bench/run/case_progress.h).
struct WorkerState {
  int total = -1;                           // the matrix's case count, skipped ones included
  std::vector<std::string> ids;             // the cases whose checks it began, in order
  std::map<std::string, std::string> axes;  // each one's axes (JSON text)
  std::string case_id, step, phase = "checks";
  void apply(const std::string& line) {
    if (line.rfind("cases ", 0) == 0) {
      total = std::atoi(line.c_str() + 6);
    } else if (line.rfind("case ", 0) == 0) {
      const size_t tab = line.find('\t');
      case_id = line.substr(5, tab == std::string::npos ? std::string::npos : tab - 5);
      axes[case_id] = tab == std::string::npos ? "{}" : line.substr(tab + 1);
      ids.push_back(case_id);
      step = "start";
      phase = "checks";
    } else if (line.rfind("step ", 0) == 0) {
      step = line.substr(5);
    } else if (line.rfind("timed ", 0) == 0) {
      case_id = line.substr(6);
      phase = "timed";
      step = "timed repetition";
    }
  }
};

struct WorkerEnd {
  int exit_code = 0;  // when it exited
  int signal = 0;     // when a signal ended it
  bool timed_out = false;
  bool crashed() const { return signal != 0 || timed_out; }
};

std::string signal_name(int s) {
  const char* abbrev = sigabbrev_np(s);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(s);
}

pid_t spawn_worker(const std::vector<std::string>& args, int progress_write_fd) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  std::vector<std::string> all = {"omnishadow"};
  all.insert(all.end(), args.begin(), args.end());
  all.insert(all.end(), {"--worker-progress-fd", std::to_string(progress_write_fd)});
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv("/proc/self/exe", argv.data());
  std::fprintf(stderr, "omnishadow: error: cannot start a worker process: %s\n", std::strerror(errno));
  _exit(127);
}

// Reads the worker's lines until it closes the pipe; kills it after `timeout_s` of silence. Then reaps it.
WorkerEnd watch_worker(pid_t pid, int read_fd, double timeout_s, WorkerState& state) {
  WorkerEnd end;
  std::string pending;
  const auto start = std::chrono::steady_clock::now();
  auto now_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  SilenceWatch silence(timeout_s, now_s());
  for (;;) {
    pass_on_signal(pid);
    pollfd p{read_fd, POLLIN, 0};
    const int ready = poll(&p, 1, 200);
    if (ready < 0 && errno != EINTR) break;
    if (ready > 0) {
      char buf[4096];
      const ssize_t n = read(read_fd, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;  // the worker ended (or closed the pipe)
      pending.append(buf, size_t(n));
      for (size_t nl; (nl = pending.find('\n')) != std::string::npos; pending.erase(0, nl + 1))
        state.apply(pending.substr(0, nl));
      silence.heard(now_s());
    } else if (silence.hung(now_s())) {
      kill(pid, SIGKILL);  // a hang: it will never answer a polite signal
      end.timed_out = true;
      break;
    }
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) pass_on_signal(pid);
  if (end.timed_out) return end;
  if (WIFSIGNALED(status)) end.signal = WTERMSIG(status);
  if (WIFEXITED(status)) end.exit_code = WEXITSTATUS(status);
  return end;
}

// `attempts`: how many times the case was run, each in a fresh worker (all of them ended so).
json crash_entry(const WorkerState& state, const WorkerEnd& end, double timeout_s, int attempts) {
  const auto known = state.axes.find(state.case_id);
  json axes = json::parse(known == state.axes.end() ? std::string("{}") : known->second, nullptr, false);
  if (axes.is_discarded()) axes = json::object();
  const std::string where =
      "in step " + state.step + (state.phase == "timed" ? " of the timed rounds" : " of the checks");
  char timeout[64];
  std::snprintf(timeout, sizeof timeout, "%g", timeout_s);
  const std::string what = end.timed_out ? "no progress for " + std::string(timeout) + " s (killed)"
                                         : "the process died by " + signal_name(end.signal);
  json crash = {{"phase", state.phase}, {"step", state.step}, {"attempts", attempts}};
  if (end.timed_out)
    crash["timeout_s"] = timeout_s;
  else
    crash["signal"] = signal_name(end.signal);
  // Only a death by a signal is run again: earlier attempts died so, the last one may have hung.
  const std::string n = std::to_string(attempts);
  const std::string each = attempts <= 1   ? ""
                           : end.timed_out ? " (at its attempt " + n + "; the earlier ones died by a signal)"
                                           : " (at each of its " + n + " attempts, each in a fresh process)";
  return {{"id", state.case_id},
          {"axes", axes},
          {"status", std::string(to_string(Status::crashed))},
          {"reason", "crashed: " + what + " " + where + each + "; the run went on in a fresh process"},
          {"crash", crash}};
}

// One worker's share of the run: its results file and which of its cases are kept (all, unless it crashed:
// then the ones before the crash; the crashed case and those after it are another's).
struct Part {
  std::string results;
  std::set<std::string> kept;  // empty with all_kept
  bool all_kept = false;
  json crash;  // null unless it ended in a crash
};

bool benchmark_of(const json& b, const std::set<std::string>& ids) {
  const std::string name = b.value("name", "");
  for (const std::string& id : ids)
    if (name.rfind(id + "/", 0) == 0 || name == id) return true;
  return false;
}

// fails_run() of a status as results.json spells it; text that names no Status fails nothing.
bool status_fails_run(const std::string& status) {
  const std::optional<Status> s = status_named(status);
  return s && fails_run(*s);
}

// Every part's kept cases in matrix order, each crash in its place, into OUT/results.json; a case that
// finished after crashing (`flaky`: its id to the earlier attempts' crashes) carries them as
// `crashed_before`. `complete`: every case of the matrix has its result (a crashed case's is `crashed`),
// unless the last worker said otherwise; `stopped_by`: the signal that stopped the run before its last case
// (empty: none). Returns whether a kept case's status fails a --check run.
bool merge_parts(const std::vector<Part>& parts, const std::map<std::string, json>& flaky,
                 const std::string& out_dir, bool complete, const std::string& stopped_by) {
  json merged, cases = json::array(), benchmarks = json::array(), crashes = json::array();
  bool fails = false;
  for (const Part& part : parts) {
    if (fs::exists(part.results)) {
      const json doc = json::parse(read_file(part.results));
      std::set<std::string> ids = part.kept;
      for (json c : doc["omnishadow"]["cases"]) {
        const std::string id = c.value("id", "");
        if (!part.all_kept && !ids.count(id)) continue;
        if (const auto f = flaky.find(id); f != flaky.end()) c["crashed_before"] = f->second;
        fails = fails || status_fails_run(c.value("status", ""));
        cases.push_back(c), ids.insert(id);
      }
      for (const json& b : doc.value("benchmarks", json::array()))
        if (benchmark_of(b, ids)) benchmarks.push_back(b);
      merged = doc;  // the last part's context, devices and options
    }
    if (!part.crash.is_null()) cases.push_back(part.crash), crashes.push_back(part.crash["id"]);
  }
  if (merged.is_null()) merged = {{"omnishadow", json::object()}};
  if (!parts.back().all_kept) merged["omnishadow"]["complete"] = complete;  // else the last worker's own word
  if (!stopped_by.empty()) merged["omnishadow"]["stopped_by"] = stopped_by;
  merged["omnishadow"]["cases"] = cases;
  merged["benchmarks"] = benchmarks;
  merged["omnishadow"]["crashed_cases"] = crashes;
  json flaky_ids = json::array();
  for (const auto& [id, before] : flaky) flaky_ids.push_back(id);
  merged["omnishadow"]["flaky_cases"] = flaky_ids;
  merged["omnishadow"]["worker_processes"] = parts.size();
  write_file_atomic((fs::path(out_dir) / "results.json").string(), merged.dump(2) + "\n");
  return fails || !crashes.empty();
}

void report_crashes(const std::vector<Part>& parts, const std::map<std::string, json>& flaky,
                    const std::string& out_dir) {
  std::string text;
  if (std::any_of(parts.begin(), parts.end(), [](const Part& p) { return !p.crash.is_null(); }))
    text += "\n## Crashed cases (each cost its process; a fresh one went on from the next case)\n";
  for (const Part& p : parts)
    if (!p.crash.is_null())
      text += "- `" + p.crash["id"].get<std::string>() + "`: " + p.crash["reason"].get<std::string>() + "\n";
  if (!flaky.empty())
    text += "\n## Flaky cases (the process died in them, then a fresh one finished them: a flaky driver)\n";
  for (const auto& [id, before] : flaky) {
    const json& last = before.back();
    text += "- `" + id + "`: finished at attempt " + std::to_string(before.size() + 1) + "; attempt " +
            std::to_string(before.size()) + " died by " + last.value("signal", "?") + " in step " +
            last.value("step", "?") +
            (last.value("phase", "") == "timed" ? " of the timed rounds" : " of the checks") + "\n";
  }
  std::cout << text;
  const fs::path summary = fs::path(out_dir) / "summary.md";
  try {
    write_file_atomic(summary.string(),
                      (fs::exists(summary) ? read_file(summary.string()) : std::string()) + text);
  } catch (const std::exception& e) {
    print_error(e.what());
  }
}

// The case a crash interrupted and its attempts so far: run again while retries last (died by a signal only).
struct Retry {
  std::string case_id;
  json crashes = json::array();  // each attempt's crash record (phase, step, signal)
  int attempts() const { return int(crashes.size()); }
};

// One worker from case `skip` on (`attempt` at that case), its results into `results` (OUT's when empty).
WorkerEnd run_worker(const IsolationSettings& settings, int skip, int attempt, const std::string& results,
                     WorkerState& state) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  fcntl(fds[0], F_SETFD, FD_CLOEXEC);
  std::vector<std::string> args = settings.args;
  args.insert(args.end(), {"--worker-skip", std::to_string(skip)});
  if (attempt > 0) args.insert(args.end(), {"--worker-attempt", std::to_string(attempt)});
  if (!results.empty()) args.insert(args.end(), {"--worker-results", results});
  const pid_t pid = spawn_worker(args, fds[1]);
  close(fds[1]);
  if (pid < 0)
    throw std::runtime_error(std::string("cannot start a worker process: ") + std::strerror(errno));
  const WorkerEnd end = watch_worker(pid, fds[0], settings.case_timeout_s, state);
  close(fds[0]);
  return end;
}

// The parts merged into OUT (results.json, summary.md) and the run's exit code.
int finish_parts(const IsolationSettings& settings, const std::vector<Part>& parts,
                 const std::map<std::string, json>& flaky, int exit_code) {
  const bool stopped = g_stop_signal != 0 && !parts.back().all_kept;
  const bool kept_fail = merge_parts(parts, flaky, settings.out_dir, !stopped,
                                     stopped ? (g_stop_signal == SIGINT ? "SIGINT" : "SIGTERM") : "");
  report_crashes(parts, flaky, settings.out_dir);
  std::error_code ec;
  fs::remove_all(fs::path(settings.out_dir) / ".parts", ec);
  std::fprintf(stderr, "omnishadow: results of %zu worker processes merged into %s\n", parts.size(),
               (fs::path(settings.out_dir) / "results.json").string().c_str());
  if (exit_code == 130 || exit_code == 143 || exit_code == 2) return exit_code;
  const bool crashed =
      std::any_of(parts.begin(), parts.end(), [](const Part& p) { return !p.crash.is_null(); });
  if (crashed) return 1;
  // Only flaky cases: the run's verdict is its cases' (the last worker's exit covers its own cases only).
  return exit_code != 0 || (settings.check && kept_fail) ? 1 : 0;
}

}  // namespace

bool is_worker_argument(const std::string& arg) { return arg.rfind("--worker-", 0) == 0; }

int supervise_run(const IsolationSettings& settings) {
  std::signal(SIGINT, forward_later);
  std::signal(SIGTERM, forward_later);
  const fs::path parts_dir = fs::path(settings.out_dir) / ".parts";
  const std::string first_results = (fs::path(settings.out_dir) / "results.json").string();
  std::vector<Part> parts;
  std::map<std::string, json> flaky;  // cases that finished after crashing: their earlier attempts' crashes
  Retry retry;
  int skip = 0, exit_code = 0;
  for (;;) {
    Part part;
    part.results =
        parts.empty() ? first_results : (parts_dir / (std::to_string(parts.size()) + ".json")).string();
    WorkerState state;
    const WorkerEnd end =
        run_worker(settings, skip, retry.attempts(), parts.empty() ? std::string() : part.results, state);
    // The case run again finished when this worker got past it.
    if (retry.attempts() > 0 && (!end.crashed() || state.case_id != retry.case_id) &&
        std::find(state.ids.begin(), state.ids.end(), retry.case_id) != state.ids.end()) {
      flaky[retry.case_id] = retry.crashes;
      retry = Retry{};
    }
    if (!end.crashed()) {
      part.all_kept = true;
      parts.push_back(part);
      exit_code = end.exit_code;
      break;
    }
    if (state.case_id.empty()) {  // before any case: nothing to blame, nothing to skip
      print_error("the run's process died before its first case (" +
                  (end.timed_out ? std::string("no progress") : signal_name(end.signal)) + ")");
      return 1;
    }
    if (state.case_id != retry.case_id) retry = Retry{state.case_id};
    json crash = crash_entry(state, end, settings.case_timeout_s, retry.attempts() + 1);
    retry.crashes.push_back(crash["crash"]);
    const auto at = std::find(state.ids.begin(), state.ids.end(), state.case_id);
    part.kept.insert(state.ids.begin(), at);
    skip += int(at - state.ids.begin());
    if (!end.timed_out && retry.attempts() <= settings.crash_retries && g_stop_signal == 0) {
      std::fprintf(stderr,
                   "omnishadow: %s died by %s; running it again in a fresh process (attempt %d of %d)\n",
                   state.case_id.c_str(), signal_name(end.signal).c_str(), retry.attempts() + 1,
                   settings.crash_retries + 1);
    } else {
      part.crash = crash;
      if (retry.attempts() > 1)
        part.crash["crash"]["earlier"] = json(retry.crashes.begin(), retry.crashes.end() - 1);
      std::fprintf(stderr, "omnishadow: %s %s\n", state.case_id.c_str(),
                   crash["reason"].get<std::string>().c_str());
      ++skip;
      retry = Retry{};
    }
    if (parts.empty() &&
        fs::exists(first_results)) {  // the next worker writes its own part; this one is kept aside
      fs::create_directories(parts_dir);
      part.results = (parts_dir / "0.json").string();
      fs::rename(first_results, part.results);
    }
    parts.push_back(part);
    if (g_stop_signal != 0) {  // stopped: no fresh process for the cases left
      exit_code = 128 + g_stop_signal;
      break;
    }
    if (state.total >= 0 && skip >= state.total) {
      exit_code = 1;
      break;
    }
  }
  if (parts.size() == 1 && parts[0].crash.is_null())
    return exit_code;  // no crash: the worker's files are the run's
  return finish_parts(settings, parts, flaky, exit_code);
}

}  // namespace omnishadow::bench
