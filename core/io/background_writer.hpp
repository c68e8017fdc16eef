// Writes files on a thread of their own while the run goes on (pictures take
// tens of milliseconds each; the cells' step, a fraction of one). Jobs run in
// the order given; at most `pending` wait, after which post() waits too, so a
// slow disk slows the run instead of filling memory. The first job to fail
// stops the others, and its error is thrown by the next post() or finish().
#pragma once

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
  // Runs `job` on the calling thread once every job posted before is done
  // (for a caller with no core to spare: see Simulation's write_file).
  void run_here(const std::function<void()>& job);
  // Waits until every job is done; rethrows the first failure.
  void finish();

 private:
  void work();
  void rethrow_failure();

  std::size_t pending_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::function<void()>> jobs_;
  bool busy_ = false, stopping_ = false;
  std::exception_ptr failure_;
  std::thread thread_;  // last: starts once the rest is ready
};

}  // namespace fibrodem
