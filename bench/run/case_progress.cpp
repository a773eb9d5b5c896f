#include "bench/run/case_progress.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
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

void inject_fault(const RunOptions& o, const std::string& id, bool timed) {
  if (timed != o.inject_in_timed) return;
  if (!o.inject_crash.empty() && std::regex_search(id, std::regex(o.inject_crash))) {
    std::signal(SIGSEGV, SIG_DFL);  // a sanitizer's handler would report and exit 1: die by the signal, as a
                                    // driver's crash does
    std::raise(SIGSEGV);
  }
  if (!o.inject_hang.empty() && std::regex_search(id, std::regex(o.inject_hang)))
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));  // a device that never answers
}

}  // namespace omnishadow::bench
