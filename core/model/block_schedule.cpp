#include "model/block_schedule.hpp"

namespace fibrodem {

void BlockSchedule::prepare(long count, int threads) {
  if (static_cast<long>(cost_s_.size()) != count || run_count_ != threads) {
    cost_s_.assign(static_cast<std::size_t>(count), 1.0);
    runs_ = std::make_unique<Run[]>(static_cast<std::size_t>(threads));
    run_count_ = threads;
    cut(threads);
  }
  for (int t = 0; t < threads; ++t) {
    runs_[static_cast<std::size_t>(t)].next.store(start_[static_cast<std::size_t>(t)], std::memory_order_relaxed);
    runs_[static_cast<std::size_t>(t)].end = start_[static_cast<std::size_t>(t) + 1];
  }
}

void BlockSchedule::cut(int threads) {
  const long count = static_cast<long>(cost_s_.size());
  double total = 0;
  for (double c : cost_s_) total += c;
  start_.assign(static_cast<std::size_t>(threads) + 1, count);
  start_[0] = 0;
  // Thread t's run ends where the running sum comes nearest t+1 shares.
  double sum = 0;
  long i = 0;
  for (int t = 1; t < threads; ++t) {
    const double target = total * t / threads;
    while (i < count && sum + 0.5 * cost_s_[static_cast<std::size_t>(i)] < target)
      sum += cost_s_[static_cast<std::size_t>(i++)];
    start_[static_cast<std::size_t>(t)] = i;
  }
}

}  // namespace fibrodem
