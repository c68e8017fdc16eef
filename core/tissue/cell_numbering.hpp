// Which of the tissue's cells a process holds states and potentials for,
// and under which numbers. In one process, every cell under its tissue
// number. A rank of a split run (tissue/rank_cells.hpp) holds its own
// cells, numbered 0 to own() - 1, then its ghosts (other ranks' cells
// joined to its own, whose potentials its gap currents read), each list in
// increasing tissue order: a rank's per-cell arrays (V, the stimulus
// current, each cell's population) are its own cells' and its ghosts', not
// the whole tissue's. Within each list the order is the tissue's, so sums
// over a cell's neighbours and the biomarkers run in one process's order.
#pragma once

#include <cstddef>
#include <vector>

#include "tissue/rank_cells.hpp"

namespace fibrodem {

class CellNumbering {
 public:
  // Every one of `tissue_cells` cells, under its tissue number.
  explicit CellNumbering(std::size_t tissue_cells = 0) : tissue_cells_(tissue_cells), own_(tissue_cells) {}
  // A rank's share of a tissue of `tissue_cells` cells: its own, then its ghosts.
  CellNumbering(std::size_t tissue_cells, const RankCells& share);

  std::size_t tissue_cells() const { return tissue_cells_; }
  // The cells held (own, then ghosts) and the own ones among them.
  std::size_t held() const { return tissue_of_.empty() ? tissue_cells_ : tissue_of_.size(); }
  std::size_t own() const { return own_; }
  bool whole() const { return tissue_of_.empty(); }

  // The tissue number of held cell c (c < held()).
  int tissue_cell(std::size_t c) const { return tissue_of_.empty() ? static_cast<int>(c) : tissue_of_[c]; }
  // The held number of a tissue cell, or -1 if it is not held (or not in
  // the tissue).
  long held_cell(long tissue_cell) const;
  bool owns(long tissue_cell) const {
    const long c = held_cell(tissue_cell);
    return c >= 0 && static_cast<std::size_t>(c) < own_;
  }

 private:
  // Held cells whose tissue and held numbers both run on by one, by
  // increasing tissue number: a rank's part of a sheet is a few runs (one a
  // column of its block), so that held_cell searches a short list.
  struct Run {
    int first_tissue_cell, first_held_cell, count;
  };

  std::size_t tissue_cells_ = 0, own_ = 0;
  std::vector<int> tissue_of_;  // split: own cells, then ghosts; empty: every cell, by number
  std::vector<Run> runs_;
};

// `share`'s halo plan in its held numbers: each neighbour's send list as
// own cells' places (0 to owned - 1), its receive list as ghosts' places
// counted from first_ghost (own() for a CellNumbering; a solver that pads
// its own rows to whole blocks counts from its padded size).
RankCells numbered_from_ghost(const RankCells& share, std::size_t first_ghost);

}  // namespace fibrodem
