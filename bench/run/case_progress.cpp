#include "bench/run/case_progress.h"

#include <execinfo.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <regex>
#include <thread>

#include "bench/run/case_runner.h"

namespace omnishadow::bench {

void send_progress(int fd, const std::string& line) {
  if (fd < 0) return;
  const std::string text = line + "\n";
  size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = ::write(fd, text.data() + sent, text.size() - sent);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the supervisor is gone: the run goes on without it
    sent += size_t(n);
  }
}

namespace {

void write_text(const char* text) { (void)!::write(STDERR_FILENO, text, std::strlen(text)); }

void on_fatal_signal(int signal) {
  // Only async-signal-safe calls: write(2), backtrace_symbols_fd (no malloc once backtrace was primed).
  const char* name = sigabbrev_np(signal);
  write_text("omnishadow: worker died by SIG");
  write_text(name ? name : "?");
  write_text("; native frames, innermost first:\n");
  void* frames[48];
  const int n = backtrace(frames, 48);
  backtrace_symbols_fd(frames, n, STDERR_FILENO);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

void report_fatal_signals() {
  void* prime[1];
  backtrace(prime, 1);  // its first call loads libgcc_s (allocates): never inside the handler
  for (int s : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) std::signal(s, on_fatal_signal);
}

void inject_fault(const RunOptions& o, const std::string& id, bool timed) {
  if (timed != o.inject_in_timed) return;
  // The worker's first case here is the one it was started to run again (checks and timed rounds both go in
  // matrix order): its attempt is the worker's; every later case's is its first.
  static const std::string first_case = id;
  const int attempt = id == first_case ? o.worker_attempt : 0;
  if (o.inject_attempts > 0 && attempt >= o.inject_attempts) return;
  if (!o.inject_crash.empty() && std::regex_search(id, std::regex(o.inject_crash))) {
    // A worker's own handler (report_fatal_signals) prints the frames and dies by the signal; elsewhere a
    // sanitizer's handler would report and exit 1: die by the signal, as a driver's crash does.
    if (o.progress_fd < 0) std::signal(SIGSEGV, SIG_DFL);
    std::raise(SIGSEGV);
  }
  if (!o.inject_hang.empty() && std::regex_search(id, std::regex(o.inject_hang)))
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));  // a device that never answers
}

}  // namespace omnishadow::bench
