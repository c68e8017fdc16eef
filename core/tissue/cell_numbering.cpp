#include "tissue/cell_numbering.hpp"

#include <algorithm>

namespace fibrodem {

namespace {

// The place of `cell` in the sorted `cells`, or -1.
long place_in(const int* first, const int* last, long cell) {
  const int* at = std::lower_bound(first, last, cell);
  return at != last && *at == cell ? static_cast<long>(at - first) : -1;
}

}  // namespace

CellNumbering::CellNumbering(std::size_t tissue_cells, const RankCells& share)
    : tissue_cells_(tissue_cells), own_(share.owned.size()) {
  tissue_of_.reserve(share.owned.size() + share.ghosts.size());
  tissue_of_.assign(share.owned.begin(), share.owned.end());
  tissue_of_.insert(tissue_of_.end(), share.ghosts.begin(), share.ghosts.end());
}

long CellNumbering::held_cell(long tissue_cell) const {
  if (tissue_cell < 0 || static_cast<std::size_t>(tissue_cell) >= tissue_cells_) return -1;
  if (tissue_of_.empty()) return tissue_cell;
  const int* own_first = tissue_of_.data();
  const int* own_last = own_first + own_;
  if (const long c = place_in(own_first, own_last, tissue_cell); c >= 0) return c;
  const long ghost = place_in(own_last, tissue_of_.data() + tissue_of_.size(), tissue_cell);
  return ghost < 0 ? -1 : static_cast<long>(own_) + ghost;
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
