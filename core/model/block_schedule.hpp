// Blocks of cells shared between threads. Each thread owns a run of cells,
// the same run step after step so that its blocks stay in its core's cache;
// the runs are cut where the threads should finish together: at equal shares
// of the measured cost, less what a thread loses waking up late (a worker
// enters the parallel region a few microseconds after the thread that opens
// it). The cuts fall at tissue cell indices, in every population at once: a
// thread's run is the cells of each type within its stretch of the tissue,
// so it writes the new potentials of that stretch alone and reads mostly its
// own cells' neighbours for the gap junctions. (Cut in the blocks' order, one
// thread had every fibroblast, spread over the whole tissue, and both cores
// wrote nearly every cache line of the potentials each step: Fig. 3 EP on 2
// threads is 3 % faster cut at tissue indices.) Within a population the cut
// falls at a multiple of the SIMD width, so the shares are even to a few
// cells rather than to a block's worth of time (at 3129 cells there are only
// 13 blocks). A thread done with its own run then takes the pieces another
// has not yet started, so a step whose costs differ from the last (cells
// depolarising, another job on a core) still ends with both threads busy.
// Which thread computes a cell, and in which piece, changes nothing in the
// numbers.
#pragma once

#include <omp.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "model/thread_governor.hpp"

namespace fibrodem {

// Cells [begin, end) of population `population`: a block, or a piece of one.
// tissue_index: the population's cells' indices in the tissue, ascending (the
// runs are cut at these; out of order, the shares come out uneven, never
// wrong), or null (the cells then follow the blocks' order).
struct CellRange {
  std::size_t population = 0, begin = 0, end = 0;
  const int* tissue_index = nullptr;
};

class BlockSchedule {
 public:
  // Work each thread does once every piece is done: (thread, threads).
  using AfterAll = std::function<void(int, int)>;
  // f(piece) for pieces covering every block of `blocks` (each within one
  // block), on the OpenMP threads; then, if given, after_all on each thread
  // of the team. A single block runs on the calling thread without a
  // parallel region (work_split.hpp says why).
  template <class F>
  void run(const std::vector<CellRange>& blocks, F&& f, const AfterAll& after_all) {
    if (blocks.size() <= 1) {
      const auto started = Clock::now();
      if (!blocks.empty()) f(blocks[0]);
      busy_s_ = seconds(started, Clock::now());
      if (after_all) after_all(0, 1);
      return;
    }
    const auto opened = Clock::now();
    const int threads = governor_.threads();
    plan(blocks, threads);
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num(), team = omp_get_num_threads();
      if (team == threads) entered_s_[static_cast<std::size_t>(t)] = seconds(opened, Clock::now());
      // Its own run first, then the others' (a smaller team than asked for,
      // e.g. when nested, takes every run the same way).
      for (int k = 0; k < threads; ++k) {
        Run& run = runs_[static_cast<std::size_t>(team == threads ? (t + k) % threads : k)];
        for (long i; (i = run.next.fetch_add(1, std::memory_order_relaxed)) < run.end;) {
          const auto started = Clock::now();
          f(pieces_[static_cast<std::size_t>(i)]);
          piece_s_[static_cast<std::size_t>(i)] = seconds(started, Clock::now());
        }
      }
      if (after_all) {
#pragma omp barrier
        after_all(t, team);
      }
    }
    learn(blocks, threads);
    governor_.record(threads, seconds(opened, Clock::now()));
  }

  // Thread t's own run in the last step (the pieces it takes first).
  std::vector<CellRange> run_of(int t) const {
    const Run& run = runs_[static_cast<std::size_t>(t)];
    return {pieces_.begin() + run.first, pieces_.begin() + run.end};
  }
  // The pieces' wall time in the last run, summed over threads.
  double busy_s() const { return busy_s_; }
  // solver.threads "auto": see ThreadGovernor.
  ThreadGovernor& governor() { return governor_; }
  const ThreadGovernor& governor() const { return governor_; }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds(Clock::time_point from, Clock::time_point to) {
    return std::chrono::duration<double>(to - from).count();
  }
  static constexpr double kSmoothing = 0.2;  // weight of the latest measurement
  struct alignas(64) Run {                   // (a cache line each: no false sharing)
    std::atomic<long> next{0};               // the next piece not yet taken
    long first = 0, end = 0;
  };
  // Cuts the blocks into pieces and the pieces into the threads' runs.
  void plan(const std::vector<CellRange>& blocks, int threads);
  // Each population's size, each block's place in the blocks' order, and the
  // position after every cell's.
  void lay_out(const std::vector<CellRange>& blocks);
  // The first position with `cost` before it (searched from `position`, the
  // last step's, and left there), and each population's cell index there (a
  // multiple of the SIMD width) in cut_.
  void cut_at(const std::vector<CellRange>& blocks, double cost, std::size_t& position);
  // Cells of block j before position `at` (a tissue index, or a place in the blocks' order).
  std::size_t cells_before(const std::vector<CellRange>& blocks, std::size_t j, std::size_t at) const;
  // Folds the pieces' times and the threads' late starts into the estimates.
  void learn(const std::vector<CellRange>& blocks, int threads);

  std::vector<double> cost_per_cell_s_;  // per block, smoothed
  std::vector<double> late_s_;           // per thread: smoothed start after the region opened
  std::vector<double> entered_s_;        // per thread, this step
  std::vector<CellRange> pieces_;
  std::vector<std::size_t> piece_block_;  // the block each piece is part of
  std::vector<double> piece_s_;           // wall time of each piece, this step
  std::vector<double> block_s_;           // wall time of each block, this step
  std::vector<std::size_t> order_start_;  // per block: its first cell's place in the blocks' order
  std::vector<std::size_t> population_size_, cut_, previous_cut_;  // per population
  std::vector<std::size_t> cut_position_;  // per thread: where its run ended, last step
  std::size_t end_position_ = 0;           // after every cell's position
  double busy_s_ = 0;
  std::unique_ptr<Run[]> runs_;
  int run_count_ = 0, run_capacity_ = 0;
  ThreadGovernor governor_;
};

}  // namespace fibrodem
