// The halo exchange of a run split over ranks (docs/guide/parallel.md): before the
// gap-junction currents are computed, each rank sends the potentials of its
// cells that other ranks' cells are joined to, and receives those of its
// ghost cells, in V_mV (by the numbers of the plan it is given: the run's
// held numbers, tissue/cell_numbering.hpp). Buffers are made once: an
// exchange allocates nothing.
#pragma once

#include <vector>

#include "util/rank_group.hpp"
#include "tissue/rank_cells.hpp"

namespace fibrodem {

class HaloExchange {
 public:
  HaloExchange(RankGroup& ranks, const RankCells& share);
  HaloExchange(const HaloExchange&) = delete;  // messages_ point into the buffers
  HaloExchange& operator=(const HaloExchange&) = delete;

  // V_mV of every ghost cell from its rank; this rank's cells' V_mV to theirs.
  void refresh(double* V_mV);
  long long exchanges() const { return exchanges_; }

 private:
  RankGroup& ranks_;
  std::vector<HaloNeighbour> neighbours_;
  std::vector<std::vector<double>> send_, receive_;
  std::vector<HaloMessage> messages_;
  long long exchanges_ = 0;
};

}  // namespace fibrodem
