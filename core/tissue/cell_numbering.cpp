#include "tissue/cell_numbering.hpp"

#include <algorithm>

namespace fibrodem {

CellNumbering::CellNumbering(std::size_t tissue_cells, const RankCells& share)
    : tissue_cells_(tissue_cells), own_(share.owned.size()) {
  tissue_of_.reserve(share.owned.size() + share.ghosts.size());
  tissue_of_.assign(share.owned.begin(), share.owned.end());
  tissue_of_.insert(tissue_of_.end(), share.ghosts.begin(), share.ghosts.end());
  for (std::size_t c = 0; c < tissue_of_.size(); ++c) {
    const int cell = tissue_of_[c];
    Run* last = runs_.empty() ? nullptr : &runs_.back();
    if (last && last->first_tissue_cell + last->count == cell &&
        static_cast<std::size_t>(last->first_held_cell + last->count) == c)
      ++last->count;
    else
      runs_.push_back({cell, static_cast<int>(c), 1});
  }
  // (The own cells' runs, then the ghosts': each list in tissue order, the two merged.)
  std::sort(runs_.begin(), runs_.end(),
            [](const Run& a, const Run& b) { return a.first_tissue_cell < b.first_tissue_cell; });
}

long CellNumbering::held_cell(long tissue_cell) const {
  if (tissue_cell < 0 || static_cast<std::size_t>(tissue_cell) >= tissue_cells_) return -1;
  if (tissue_of_.empty()) return tissue_cell;
  // The last run starting at or before the cell.
  const auto after = std::upper_bound(runs_.begin(), runs_.end(), tissue_cell,
                                      [](long cell, const Run& run) { return cell < run.first_tissue_cell; });
  if (after == runs_.begin()) return -1;
  const Run& run = *(after - 1);
  const long offset = tissue_cell - run.first_tissue_cell;
  return offset < run.count ? run.first_held_cell + offset : -1;
}

RankCells numbered_from_ghost(const RankCells& share, std::size_t first_ghost) {
  const auto place = [](const std::vector<int>& cells, int cell) {
    return static_cast<int>(std::lower_bound(cells.begin(), cells.end(), cell) - cells.begin());
  };
  RankCells numbered;
  numbered.rank = share.rank;
  for (const HaloNeighbour& neighbour : share.neighbours) {
    HaloNeighbour n{neighbour.rank, {}, {}};
    for (int cell : neighbour.send) n.send.push_back(place(share.owned, cell));
    for (int cell : neighbour.receive) n.receive.push_back(static_cast<int>(first_ghost) + place(share.ghosts, cell));
    numbered.neighbours.push_back(std::move(n));
  }
  return numbered;
}

}  // namespace fibrodem
