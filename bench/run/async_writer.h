#pragma once
// Image files encoded and written on a worker thread while the next case's check frame renders: on a GPU the
// PNG and PFM encoding of every case was most of the untimed part. The queue is bounded (submit waits while
// it is full, so memory stays a few cases' images) and drained before any timed frame, so the worker never
// runs beside a measurement.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace omnishadow::bench {

class AsyncWriter {
 public:
  explicit AsyncWriter(size_t max_pending = 8);
  ~AsyncWriter();  // drains, then stops the worker
  AsyncWriter(const AsyncWriter&) = delete;
  AsyncWriter& operator=(const AsyncWriter&) = delete;

  // Runs `job` on the worker; `label` (a case id) names it in a failure.
  void submit(std::string label, std::function<void()> job);
  // Waits until every submitted job ran; returns the failures as (label, message) and forgets them.
  std::vector<std::pair<std::string, std::string>> drain();

 private:
  void work();

  const size_t max_pending_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<std::string, std::function<void()>>> queue_;
  size_t running_ = 0;
  bool stopping_ = false;
  std::vector<std::pair<std::string, std::string>> failures_;
  std::thread worker_;  // last: started when everything above exists
};

}  // namespace omnishadow::bench
