// The DEM of a run split over ranks where the DEM itself is not split
// (docs/guide/parallel.md, Design 11: multirate; else
// mechanics/dem_split.hpp): rank 0 steps the whole tissue's
// mechanics. At the end of every cell step each rank sends
// its own cells' lengths relative to rest (SL / SL_rest, from their
// myofilaments) to rank 0, which places them by tissue number and advances
// the mechanics with them: the values, in the order, one process hands its
// DEM. Nothing goes back: the DEM drives nothing in the cells (their
// stretch-activated current reads each cell's own sarcomere length,
// integrate/cell_system.hpp), so the other ranks only send.
#pragma once

#include <vector>

#include "integrate/cell_system.hpp"
#include "run/mechanics_coupling.hpp"
#include "run/rank_layout.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

class MechanicsOverRanks {
 public:
  // `layout`: every rank's cells (run/rank_layout.hpp); it must outlive
  // this. Buffers are made at the first advance, once.
  MechanicsOverRanks(RankGroup& ranks, const RankLayout& layout);

  // Collective (every rank at the end of the same step): the cells' lengths
  // at t_ms to rank 0, whose `mechanics` then steps up to t_ms (null on the
  // other ranks, which return once their values are sent).
  void advance(double t_ms, const CellSystem& system, MechanicsCoupling* mechanics);

 private:
  RankGroup& ranks_;
  const RankLayout& layout_;
  std::vector<double> own_ratio_;      // this rank's cells, in the layout's order
  std::vector<double> gathered_;       // rank 0: every cell, rank after rank
  std::vector<double> ratio_by_cell_;  // rank 0: every cell, by tissue number
};

}  // namespace fibrodem
