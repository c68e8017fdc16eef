#include "io/background_writer.hpp"

namespace fibrodem {

BackgroundWriter::BackgroundWriter(std::size_t pending) : pending_(pending == 0 ? 1 : pending) {}

BackgroundWriter::~BackgroundWriter() {
  if (!thread_.joinable()) return;
  {
    std::unique_lock lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void BackgroundWriter::post(std::function<void()> job) {
  std::unique_lock lock(mutex_);
  if (!thread_.joinable()) thread_ = std::thread([this] { work(); });
  changed_.wait(lock, [&] { return jobs_.size() < pending_ || failure_; });
  if (failure_) rethrow_failure();
  jobs_.push_back(std::move(job));
  unfinished_.fetch_add(1, std::memory_order_relaxed);
  changed_.notify_all();
}

void BackgroundWriter::finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return idle() || failure_; });
  if (failure_) rethrow_failure();
}

void BackgroundWriter::rethrow_failure() {
  std::exception_ptr failure = failure_;
  failure_ = nullptr;  // thrown once
  unfinished_.fetch_sub(jobs_.size(), std::memory_order_relaxed);
  jobs_.clear();
  std::rethrow_exception(failure);
}

void BackgroundWriter::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !jobs_.empty() || stopping_; });
    if (jobs_.empty()) return;  // stopping, and nothing left to write
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    std::exception_ptr failure;
    try {
      job();
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    unfinished_.fetch_sub(1, std::memory_order_release);
    if (failure && !failure_) failure_ = failure;
    changed_.notify_all();
  }
}

}  // namespace fibrodem
