#pragma once
// How long a worker process has said nothing, against --case-timeout-s: the supervisor's hang rule
// (bench/cli/case_isolation.cpp). Times are seconds on any monotonic clock the caller reads, so that a test
// drives time itself instead of waiting for it (tests/silence_watch_test.cpp).
namespace omnishadow::bench {

class SilenceWatch {
 public:
  SilenceWatch(double timeout_s, double now_s) : timeout_s_(timeout_s), last_heard_s_(now_s) {}
  // A line from the worker: it is making progress, and the silence starts again from now.
  void heard(double now_s) { last_heard_s_ = now_s; }
  // More than the timeout since the last line (exactly the timeout is still patience).
  bool hung(double now_s) const { return now_s - last_heard_s_ > timeout_s_; }
  double silent_s(double now_s) const { return now_s - last_heard_s_; }

 private:
  double timeout_s_;
  double last_heard_s_;
};

}  // namespace omnishadow::bench
