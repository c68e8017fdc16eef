// Blocks of cells shared between threads: each thread owns a contiguous run
// of blocks of equal measured cost, the same run step after step, so that its
// blocks stay in its core's cache; a thread done with its own run then takes
// the blocks another has not yet started (from that run's front), so a step
// whose costs differ from the last (cells depolarising, another job on a
// core) still ends with both threads busy. (A plain dynamic schedule moves
// about half the blocks, with their states, between cores at every step.)
// Each block's cost is its wall time, smoothed over steps; after each pass the
// runs are re-cut at equal shares of the total. Which thread computes a block
// changes nothing in the numbers.
#pragma once

#include <omp.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <vector>

namespace fibrodem {

class BlockSchedule {
 public:
  // f(i) for each block i in [0, count), on the OpenMP threads; one block on
  // the calling thread without a parallel region (work_split.hpp says why).
  template <class F>
  void run(long count, F&& f) {
    if (count == 1) return f(0L);
    const int threads = omp_get_max_threads();
    prepare(count, threads);
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num(), team = omp_get_num_threads();
      // Its own run first, then the others' (a smaller team than asked for,
      // e.g. when nested, takes every run the same way).
      for (int k = 0; k < threads; ++k) {
        const int owner = team == threads ? (t + k) % threads : k;
        Run& run = runs_[static_cast<std::size_t>(owner)];
        for (long i; (i = run.next.fetch_add(1, std::memory_order_relaxed)) < run.end;) {
          const auto started = std::chrono::steady_clock::now();
          f(i);
          cost_s_[static_cast<std::size_t>(i)] +=
              kSmoothing * (std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() -
                            cost_s_[static_cast<std::size_t>(i)]);
        }
      }
    }
    cut(threads);
  }

 private:
  static constexpr double kSmoothing = 0.2;  // weight of the latest time in a block's cost
  struct Run {
    std::atomic<long> next{0};  // the next block not yet taken
    long end = 0;
  };
  // Sizes the costs and runs (anew when the count or the threads change) and
  // rewinds each run to its start.
  void prepare(long count, int threads);
  // Cuts the blocks into the threads' runs at equal shares of the total cost.
  void cut(int threads);
  std::vector<double> cost_s_;  // per block
  std::vector<long> start_;     // thread t owns blocks [start_[t], start_[t + 1])
  std::unique_ptr<Run[]> runs_;
  int run_count_ = 0;
};

}  // namespace fibrodem
