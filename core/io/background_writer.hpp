// Writes files on a thread of their own while the run goes on (pictures take
// tens of milliseconds each; the cells' step, a fraction of one). Jobs run in
// the order given; at most `pending` wait, after which post() waits too, so a
// slow disk slows the run instead of filling memory. The first job to fail
// stops the others, and its error is thrown by the next post() or finish().
// The thread starts with the first job: a run that writes nothing in the
// background (a single cell under CVODE, a sweep's point) creates none.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace fibrodem {

class BackgroundWriter {
 public:
  explicit BackgroundWriter(std::size_t pending = 2);
  ~BackgroundWriter();  // waits for the jobs; errors are dropped here (call finish() to see them)
  BackgroundWriter(const BackgroundWriter&) = delete;
  BackgroundWriter& operator=(const BackgroundWriter&) = delete;

  void post(std::function<void()> job);
  // Waits until every job is done; rethrows the first failure.
  void finish();
  // No job waiting or running (for a run that lent the writer a core: see
  // Simulation's write_file).
  bool idle() const { return unfinished_.load(std::memory_order_acquire) == 0; }

 private:
  void work();
  void rethrow_failure();

  std::size_t pending_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::atomic<std::size_t> unfinished_{0};  // posted and not yet done (changed under mutex_)
  std::exception_ptr failure_;
  std::thread thread_;  // started by the first post()
};

}  // namespace fibrodem
