// Reductions over the ranks of a split run that every rank computes with the
// same bits (docs/guide/parallel.md): each rank's value is gathered by every rank,
// which adds them in rank order (a sum's rounding then depends on the number
// of ranks only, not on the order messages arrive in) or takes their largest
// (exact in any order). One collective call a reduction; nothing allocated.
#pragma once

#include <vector>

#include "util/rank_group.hpp"

namespace fibrodem {

class RankReductions {
 public:
  explicit RankReductions(RankGroup& ranks);
  // sum: every rank's added in rank order; largest: every rank's largest.
  void reduce(double& sum, double& largest);
  double largest(double mine);

 private:
  RankGroup& ranks_;
  std::vector<double> mine_, every_rank_;
};

}  // namespace fibrodem
