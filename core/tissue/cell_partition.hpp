// The cells' coupling graph (Tissue::cell_edges) split into parts, one per
// MPI rank of a run over several ranks (docs/guide/parallel.md): parts of nearly
// equal cell counts with few edges between them (each cut edge is a
// potential sent between two ranks at every coupling evaluation).
//
// Every rank builds the same tissue from the same scene and seed, and the
// partition is a function of the tissue alone (Scotch with a fixed strategy,
// a fixed random seed and its deterministic mode, on one thread), so every
// rank computes the same partition without communicating.
#pragma once

#include <cstddef>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

// Load imbalance Scotch is asked to keep within: no part holds more than
// (1 + kPartImbalance) times the mean cell count (rounded up to whole cells).
inline constexpr double kPartImbalance = 0.01;

struct CellPartition {
  int parts = 1;
  std::vector<int> part_of;  // per cell: its part, in [0, parts)

  std::vector<std::size_t> sizes() const;  // cells per part
  // The cells of part p, in increasing global order.
  std::vector<int> cells_of(int part) const;
  // Edges of the tissue's cell graph whose two cells lie in different parts.
  std::size_t cut_edges(const Tissue& tissue) const;
};

// Splits the tissue's cells into `parts` parts (1 <= parts <= cell count;
// std::invalid_argument naming both otherwise). One part: every cell in part
// 0, without Scotch. Cells without edges (isolated fibroblasts) are placed
// like any other, counted for the balance.
CellPartition partition_cells(const Tissue& tissue, int parts);

}  // namespace fibrodem
