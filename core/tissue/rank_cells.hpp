// One rank's share of a partitioned tissue (tissue/cell_partition.hpp): the
// cells it owns, the ghost cells (other ranks' cells joined to one of its
// own) whose potentials its gap-junction currents read, and the plan of the
// halo exchange that refreshes them: which of its cells each neighbouring
// rank needs, and which ghosts each sends. Every list is in increasing
// global cell order, so two ranks agree on a message's layout without
// sending it, and a cell's coupling sums run in the same order on any number
// of ranks (docs/guide/parallel.md).
#pragma once

#include <vector>

#include "tissue/cell_partition.hpp"

namespace fibrodem {

struct HaloNeighbour {
  int rank = -1;
  std::vector<int> send;     // own cells joined to one of rank's cells
  std::vector<int> receive;  // rank's cells joined to one of ours (ghosts)
};

struct RankCells {
  int rank = 0;
  std::vector<int> owned;
  std::vector<int> ghosts;  // every neighbour's receive list, merged
  std::vector<HaloNeighbour> neighbours;  // by increasing rank; only ranks sharing an edge
};

// Rank `rank`'s share (0 <= rank < parts), each cell's part asked of
// `part_of` (a partition's cuts need not hold every cell's part); the
// tissue's graph must hold every edge with one of the rank's cells at an
// end, and a tissue holding part of its cells its own (the cells asked
// are then those held).
RankCells rank_cells(const Tissue& tissue, int parts, const PartOfCell& part_of, int rank);
RankCells rank_cells(const Tissue& tissue, const CellPartition& partition, int rank);

}  // namespace fibrodem
