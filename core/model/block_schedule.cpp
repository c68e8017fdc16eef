#include "model/block_schedule.hpp"

#include <algorithm>
#include <limits>

#include "model/simd.hpp"

namespace fibrodem {

void BlockSchedule::plan(const std::vector<CellRange>& blocks, int threads) {
  const auto n_threads = static_cast<std::size_t>(threads);
  if (cost_per_cell_s_.size() != blocks.size()) cost_per_cell_s_.assign(blocks.size(), 1.0);  // unknown: even
  if (run_count_ != threads) {  // (solver.threads auto switches between counts: no allocation then)
    if (threads > run_capacity_) {
      runs_ = std::make_unique<Run[]>(n_threads);
      run_capacity_ = threads;
    }
    run_count_ = threads;
    late_s_.assign(n_threads, 0.0);
    entered_s_.assign(n_threads, 0.0);
  }
  double total = 0, late_total = 0;
  for (std::size_t j = 0; j < blocks.size(); ++j)
    total += cost_per_cell_s_[j] * static_cast<double>(blocks[j].end - blocks[j].begin);
  for (double late : late_s_) late_total += late;
  // Every thread should be done at `finish` (from the region's opening).
  const double finish = (total + late_total) / threads;
  pieces_.clear();
  piece_block_.clear();
  std::size_t j = 0, taken = 0;  // cells of block j already given to a thread
  double given = 0;              // their cost
  for (std::size_t t = 0; t < n_threads; ++t) {
    runs_[t].next.store(static_cast<long>(pieces_.size()), std::memory_order_relaxed);
    const double until = t + 1 == n_threads ? std::numeric_limits<double>::infinity()
                                            : given + std::max(0.0, finish - late_s_[t]);
    while (j < blocks.size()) {
      const CellRange& block = blocks[j];
      const std::size_t left = block.end - block.begin - taken;
      const double per_cell = std::max(cost_per_cell_s_[j], 1e-15);
      std::size_t cells = left;
      if (given + per_cell * static_cast<double>(left) > until) {  // the cut falls in this block
        const double fit = (until - given) / per_cell / static_cast<double>(simd::kLanes);
        cells = std::min(left, static_cast<std::size_t>(fit + 0.5) * simd::kLanes);
      }
      if (cells > 0) {
        pieces_.push_back({block.population, block.begin + taken, block.begin + taken + cells});
        piece_block_.push_back(j);
        given += per_cell * static_cast<double>(cells);
        taken += cells;
      }
      if (taken == block.end - block.begin) {
        ++j;
        taken = 0;
      }
      if (cells < left) break;  // this thread's share is full
    }
    runs_[t].end = static_cast<long>(pieces_.size());
  }
  piece_s_.assign(pieces_.size(), 0.0);
}

void BlockSchedule::learn(const std::vector<CellRange>& blocks, int threads) {
  // (Pieces of one block may have run on different threads: summed here, after the loop.)
  block_s_.assign(blocks.size(), 0.0);
  busy_s_ = 0;
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    block_s_[piece_block_[i]] += piece_s_[i];
    busy_s_ += piece_s_[i];
  }
  for (std::size_t j = 0; j < blocks.size(); ++j) {
    const double per_cell = block_s_[j] / static_cast<double>(blocks[j].end - blocks[j].begin);
    cost_per_cell_s_[j] += kSmoothing * (per_cell - cost_per_cell_s_[j]);
  }
  for (std::size_t t = 0; t < static_cast<std::size_t>(threads); ++t)
    late_s_[t] += kSmoothing * (entered_s_[t] - late_s_[t]);
}

}  // namespace fibrodem
