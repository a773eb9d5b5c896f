#include "bench/run/async_writer.h"

#include <exception>

namespace omnishadow::bench {

AsyncWriter::AsyncWriter(size_t max_pending) : max_pending_(max_pending), worker_([this] { work(); }) {}

AsyncWriter::~AsyncWriter() {
  drain();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void AsyncWriter::submit(std::string label, std::function<void()> job) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < max_pending_; });
  queue_.emplace_back(std::move(label), std::move(job));
  changed_.notify_all();
}

std::vector<std::pair<std::string, std::string>> AsyncWriter::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.empty() && running_ == 0; });
  std::vector<std::pair<std::string, std::string>> out;
  out.swap(failures_);
  return out;
}

void AsyncWriter::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, nothing left
    auto [label, job] = std::move(queue_.front());
    queue_.pop_front();
    ++running_;
    changed_.notify_all();  // a slot is free
    lock.unlock();
    std::string failure;
    try {
      job();
    } catch (const std::exception& e) {
      failure = e.what();
    }
    lock.lock();
    if (!failure.empty()) failures_.emplace_back(label, failure);
    --running_;
    changed_.notify_all();
  }
}

}  // namespace omnishadow::bench
