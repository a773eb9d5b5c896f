// `omnishadow report` and `omnishadow history`: pages written in Python (scripts/analysis/report.py and
// history.py, with matplotlib and numpy), run by Debian's /usr/bin/python3 in a child process. With --db the
// runs they read come from the results store: fetched into a temporary folder first (the folders `fetch`
// writes), removed after, so a page from the store is the page from the same runs' folders.

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>

#include "bench/cli/commands.h"
#include "bench/report/results_store.h"

namespace omnishadow::bench {
namespace {

namespace fs = std::filesystem;
const std::string kPython = "/usr/bin/python3";

// A fresh folder under $TMPDIR (or /tmp), removed with what it holds when this goes.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/omnishadow-store-XXXXXX";
    if (!mkdtemp(pattern.data()))
      throw StoreError("cannot make a temporary folder: " + std::string(std::strerror(errno)));
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The script's exit code; 2 with one line when Python or the script is missing or it dies by a signal.
int run_python(const std::string& who, const std::string& script, const std::vector<std::string>& args) {
  std::error_code ec;
  if (!fs::exists(kPython, ec) || !fs::exists(script, ec)) {
    print_error(who + " needs " + kPython + " and " + script +
                " (scripts/setup.sh installs Python's packages)");
    return 2;
  }
  std::vector<std::string> all = {kPython, script};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    execv(kPython.c_str(), argv.data());
    print_error(who + ": cannot run " + kPython + ": " + std::strerror(errno));
    _exit(2);
  }
  if (pid < 0) {
    print_error(who + ": cannot start " + kPython + ": " + std::strerror(errno));
    return 2;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  print_error(who + ": " + script + " died by signal " + std::to_string(WTERMSIG(status)));
  return 2;
}

// Every run of the store as run folders in `fetched` (made here; the scripts pick one device among them, as
// they do among folders): the folder holding them, or "" after one line on stderr when none can be read.
// Runs stored by an older binary without their document are counted on stderr.
std::string fetch_for(const std::string& who, const std::string& db,
                      std::optional<TemporaryFolder>& fetched) {
  try {
    fetched.emplace();
    const std::string runs = (fs::path(fetched->path()) / "runs").string();
    const FetchSummary f = fetch_into(db, {}, runs);
    if (f.without_document > 0)
      std::fprintf(stderr,
                   "omnishadow: %s --db: %d stored run(s) have no document (stored before schema 2): store "
                   "their folders again to add it\n",
                   who.c_str(), f.without_document);
    if (f.runs > 0) return runs;
    print_error(who + " --db " + redacted_store_url(db) + ": no runs stored");
  } catch (const std::exception& e) {
    print_error(who + ": " + e.what());
  }
  return "";
}

}  // namespace

int report_command(const ReportArgs& a) {
  std::error_code ec;
  // The paths first, in this process's words: the script would say them in Python's.
  if (!fs::is_regular_file(a.run, ec) && !fs::is_regular_file(fs::path(a.run) / "results.json", ec)) {
    print_error("report: " + a.run +
                " is no run (no results.json there; give a run folder or its results.json)");
    return 2;
  }
  for (const std::string& h : a.history)
    if (!fs::exists(h, ec)) {
      print_error("report --history " + h + ": no such run or folder");
      return 2;
    }
  if (!a.out.empty() &&
      (fs::is_directory(a.out, ec) || !fs::is_directory(fs::absolute(a.out).parent_path(), ec))) {
    print_error("report --out " + a.out + ": " +
                (fs::is_directory(a.out, ec) ? "is a folder; give the HTML file's path"
                                             : "its folder does not exist"));
    return 2;
  }
  std::vector<std::string> args = {a.run};
  std::vector<std::string> history = a.history;
  std::optional<TemporaryFolder> fetched;  // removed when the page is written
  if (!a.db.empty()) {
    const std::string runs = fetch_for("report", a.db, fetched);
    if (runs.empty()) return 2;
    history.push_back(runs);
  }
  if (!history.empty()) {
    args.push_back("--history");
    args.insert(args.end(), history.begin(), history.end());
  }
  if (!a.out.empty()) args.insert(args.end(), {"--out", a.out});
  return run_python("report", project_path("scripts/analysis/report.py"), args);
}

int history_command(const HistoryArgs& a, bool alerts_only) {
  if (a.runs.empty() && a.db.empty()) {
    print_error("history: give run folders (or folders of runs) or --db URL");
    return 2;
  }
  std::error_code ec;
  for (const std::string& r : a.runs)
    if (!fs::exists(r, ec)) {
      print_error("history: " + r + ": no such run or folder");
      return 2;
    }
  std::vector<std::string> args = a.runs;
  // The accepted steps of the file (given, or the project's) and, with --db, of the store as well; the
  // store's thresholds.
  args.insert(args.end(),
              {"--accepted", a.accepted.empty() ? project_path("results/accepted_steps.json") : a.accepted});
  std::optional<TemporaryFolder> fetched;  // removed when the history is written
  if (!a.db.empty()) {
    const std::string runs = fetch_for(alerts_only ? "alerts" : "history", a.db, fetched);
    if (runs.empty()) return 2;
    args.insert(args.end(), {runs, "--accepted", (fs::path(runs) / "accepted_steps.json").string(),
                             "--thresholds", (fs::path(runs) / "thresholds.json").string()});
  }
  if (alerts_only) args.push_back("--alerts");
  if (!a.out.empty()) args.insert(args.end(), {"--out", a.out});
  if (!a.device_key.empty()) args.insert(args.end(), {"--device-key", a.device_key});
  return run_python("history", project_path("scripts/analysis/history.py"), args);
}

}  // namespace omnishadow::bench
