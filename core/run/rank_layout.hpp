// Where every rank's own cells sit in a run split over ranks when rank 0
// gathers one value a cell: rank after rank, each rank's cells in
// increasing tissue order (the run's partition, simulation_ranks.cpp), as
// RankGroup::gather_into places them. Rank 0 gathers V for the snapshots
// and the re-entry samples, and the cells' lengths for a DEM it steps alone,
// all through gather_by_cell.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "tissue/cell_partition.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

struct RankLayout {
  std::vector<int> cells_in_rank_order;  // every cell, rank after rank
  std::vector<int> counts, offsets;      // each rank's cell count, and where its cells start

  // Rank r's cells, in increasing tissue numbers.
  std::span<const int> cells_of(int rank) const {
    const auto r = static_cast<std::size_t>(rank);
    return {cells_in_rank_order.data() + offsets[r], static_cast<std::size_t>(counts[r])};
  }
  std::size_t cell_count() const { return cells_in_rank_order.size(); }
  // What a rank other than 0 needs of it to send its own values to rank 0:
  // the counts and offsets, not every cell's place (4 bytes a cell).
  // cells_of() and cell_count() are then not to be asked.
  void keep_counts_only() { std::vector<int>().swap(cells_in_rank_order); }
};

// The layout of a partition's parts, one pass over its cells (each rank's
// cells come out in increasing tissue order).
RankLayout rank_layout(const CellPartition& partition);
// Its counts and offsets alone (RankLayout::keep_counts_only's), from each
// part's cell count.
RankLayout rank_layout_counts(const std::vector<std::size_t>& cells_per_part);

// Collective: each rank's values of its own cells, `own` (one a cell, in
// cells_of(its rank)'s order), gathered on rank 0 into `by_cell` (one a
// cell, by tissue number) through `gathered` (rank 0's buffer, rank after
// rank); both are sized here on rank 0, once, and left alone elsewhere.
void gather_by_cell(RankGroup& ranks, const RankLayout& layout, const double* own, std::vector<double>& gathered,
                    std::vector<double>& by_cell);
// The same, with this rank's values taken from `per_cell` (one a cell, by
// tissue number) at its own cells, into `own` (sized here, once).
void gather_by_cell(RankGroup& ranks, const RankLayout& layout, const std::vector<double>& per_cell,
                    std::vector<double>& own, std::vector<double>& gathered, std::vector<double>& by_cell);

}  // namespace fibrodem
