#include "run/rank_reductions.hpp"

#include <algorithm>

namespace fibrodem {

RankReductions::RankReductions(RankGroup& ranks)
    : ranks_(ranks), mine_(2, 0.0), every_rank_(2 * static_cast<std::size_t>(ranks.size()), 0.0) {}

void RankReductions::reduce(double& sum, double& largest) {
  mine_[0] = sum;
  mine_[1] = largest;
  ranks_.gather_all(mine_.data(), 2, every_rank_.data());
  sum = 0;
  for (int r = 0; r < ranks_.size(); ++r) {
    sum += every_rank_[2 * static_cast<std::size_t>(r)];
    largest = std::max(largest, every_rank_[2 * static_cast<std::size_t>(r) + 1]);
  }
}

double RankReductions::largest(double mine) {
  ranks_.gather_all(&mine, 1, every_rank_.data());
  return *std::max_element(every_rank_.begin(), every_rank_.begin() + ranks_.size());
}

}  // namespace fibrodem
