// solver.threads "auto" on a machine shared with other jobs. A step on two
// threads ends when the slower is done; when another job holds a core, the
// thread waiting for it can cost more than the second thread gains (on this
// project's 2-core machine with other builds running, the Fig. 3 EP scene
// took 4.3-5.5 s on one thread and 19-21 s on two). So the governor measures
// the parallel loop's wall time per call on both thread counts and keeps the
// faster: it runs on one count for a stretch of calls, then tries the other
// for a few, and switches when that was faster by a margin. Each time the
// other count loses, the stretch doubles (up to a limit), so on a quiet
// machine the trials cost a fraction of a per cent. Results do not depend on
// the thread count, so switching changes nothing in the numbers.
// It also holds a fixed count, and lends a core to the writer of pictures
// while that has work (the cells then step on one thread fewer).
#pragma once

#include <array>

namespace fibrodem {

class ThreadGovernor {
 public:
  // A fixed count (an explicit solver.threads, or "auto" on a small scene);
  // sets OpenMP's default to it.
  void use(int threads);
  // From now on, chooses between 1 and max_threads (and sets OpenMP's default
  // to its choice, so that the run's other parallel loops follow it).
  // Without this call or use() it always takes OpenMP's default.
  void adapt(int max_threads);
  bool adapting() const { return adapting_; }
  int max_threads() const { return max_threads_; }
  // The thread count for the next call.
  int threads() const;
  // The count chosen, before any core lent.
  int chosen() const;
  // Lends `cores` cores to other work until lend(0): a picture drawn on the
  // writer's thread while the cells step. The cells then step on that many
  // fewer threads (at least one), and those calls are not measured.
  void lend(int cores);
  int lent() const { return lent_; }
  // One call's wall time on `threads` threads.
  void record(int threads, double wall_s);
  // Calls made on one thread and on more (for the run's notes), and the switches.
  long calls_on_one() const { return calls_[0]; }
  long calls_on_more() const { return calls_[1]; }
  int switches() const { return switches_; }

 private:
  static constexpr long kFirstStretch = 512, kLongestStretch = 16384;  // calls
  static constexpr long kTrial = 64;          // calls on the other count; the first half warm its caches
  static constexpr double kMargin = 0.95;     // the other count must be this much faster to win
  int other() const { return current_ == 1 ? max_threads_ : 1; }
  void begin_phase(bool trial);

  int max_threads_ = 0;     // 0: OpenMP's default
  bool adapting_ = false;
  int lent_ = 0;
  int current_ = 0;
  bool trial_ = false;      // trying the other count now
  long left_ = 0;           // calls left in this phase
  long measured_ = 0;       // calls of this phase measured so far
  double sum_s_ = 0;        // their wall time
  double current_mean_s_ = 0;  // per call on the current count, at the end of its last stretch
  long stretch_ = kFirstStretch;
  std::array<long, 2> calls_{0, 0};
  int switches_ = 0;
};

}  // namespace fibrodem
