#include "model/block_schedule.hpp"

#include <algorithm>

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
    cut_position_.assign(n_threads, 0);
  }
  double total = 0, late_total = 0;
  for (std::size_t j = 0; j < blocks.size(); ++j)
    total += cost_per_cell_s_[j] * static_cast<double>(blocks[j].end - blocks[j].begin);
  for (double late : late_s_) late_total += late;
  // Every thread should be done at `finish` (from the region's opening).
  const double finish = (total + late_total) / threads;
  lay_out(blocks);
  const std::size_t populations = population_size_.size();
  pieces_.clear();
  piece_block_.clear();
  previous_cut_.assign(populations, 0);
  double budget = 0;  // the cost of the runs so far
  for (std::size_t t = 0; t < n_threads; ++t) {
    runs_[t].first = static_cast<long>(pieces_.size());
    runs_[t].next.store(runs_[t].first, std::memory_order_relaxed);
    if (t + 1 == n_threads) {
      cut_ = population_size_;
    } else {
      budget += std::max(0.0, finish - late_s_[t]);
      cut_at(blocks, budget, cut_position_[t]);
    }
    for (std::size_t p = 0; p < populations; ++p) cut_[p] = std::max(cut_[p], previous_cut_[p]);
    for (std::size_t j = 0; j < blocks.size(); ++j) {
      const CellRange& block = blocks[j];
      const std::size_t p = block.population;
      const std::size_t begin = std::max(block.begin, previous_cut_[p]), end = std::min(block.end, cut_[p]);
      if (begin >= end) continue;
      pieces_.push_back({p, begin, end, block.tissue_index});
      piece_block_.push_back(j);
    }
    runs_[t].end = static_cast<long>(pieces_.size());
    std::swap(previous_cut_, cut_);
  }
  piece_s_.assign(pieces_.size(), 0.0);
}

void BlockSchedule::lay_out(const std::vector<CellRange>& blocks) {
  std::size_t populations = 0, order = 0;
  for (const CellRange& block : blocks) populations = std::max(populations, block.population + 1);
  population_size_.assign(populations, 0);
  order_start_.resize(blocks.size());
  end_position_ = 0;
  for (std::size_t j = 0; j < blocks.size(); ++j) {
    const CellRange& block = blocks[j];
    order_start_[j] = order;
    order += block.end - block.begin;
    population_size_[block.population] = std::max(population_size_[block.population], block.end);
    end_position_ = std::max(end_position_, block.tissue_index
                                                ? static_cast<std::size_t>(block.tissue_index[block.end - 1]) + 1
                                                : order);
  }
}

std::size_t BlockSchedule::cells_before(const std::vector<CellRange>& blocks, std::size_t j, std::size_t at) const {
  const CellRange& block = blocks[j];
  const std::size_t size = block.end - block.begin;
  if (!block.tissue_index) {
    const std::size_t start = order_start_[j];
    return std::clamp(at, start, start + size) - start;
  }
  const int *first = block.tissue_index + block.begin, *last = block.tissue_index + block.end;
  if (static_cast<std::size_t>(*first) >= at) return 0;  // (most blocks lie wholly on one side)
  if (static_cast<std::size_t>(last[-1]) < at) return size;
  return static_cast<std::size_t>(
      std::lower_bound(first, last, at, [](int cell, std::size_t x) { return static_cast<std::size_t>(cell) < x; }) -
      first);
}

void BlockSchedule::cut_at(const std::vector<CellRange>& blocks, double cost, std::size_t& position) {
  const auto short_of = [&](std::size_t at) {  // less than `cost` before `at`
    double sum = 0;
    for (std::size_t j = 0; j < blocks.size(); ++j)
      sum += std::max(cost_per_cell_s_[j], 1e-15) * static_cast<double>(cells_before(blocks, j, at));
    return sum < cost;
  };
  // The first position with `cost` before it, searched from the last step's
  // (the cut moves little between steps, and the search then reads few of
  // the tissue indices, which the cells' work has pushed out of cache).
  const std::size_t from = std::min(position, end_position_);
  std::size_t lo = from, hi = from, stride = simd::kLanes;
  if (short_of(from)) {
    for (lo = from + 1, hi = std::min(end_position_, from + stride); hi < end_position_ && short_of(hi);
         hi = std::min(end_position_, from + stride)) {
      lo = hi + 1;
      stride *= 2;
    }
  } else {
    for (lo = from >= stride ? from - stride : 0; lo > 0 && !short_of(lo); lo = from >= stride ? from - stride : 0) {
      hi = lo;
      stride *= 2;
    }
  }
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (short_of(mid)) lo = mid + 1;
    else hi = mid;
  }
  position = std::min(lo, end_position_);  // (a cost beyond the total: every cell)
  cut_.assign(population_size_.size(), 0);
  for (std::size_t j = 0; j < blocks.size(); ++j) cut_[blocks[j].population] += cells_before(blocks, j, position);
  for (std::size_t p = 0; p < cut_.size(); ++p)
    cut_[p] = std::min(population_size_[p], (cut_[p] + simd::kLanes / 2) / simd::kLanes * simd::kLanes);
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
