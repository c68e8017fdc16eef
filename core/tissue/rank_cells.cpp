#include "tissue/rank_cells.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace fibrodem {

namespace {

void sort_unique(std::vector<int>& cells) {
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
}

}  // namespace

RankCells rank_cells(const Tissue& tissue, const CellPartition& partition, int rank) {
  return rank_cells(
      tissue, partition.parts, [&partition](int cell) { return partition.part_of[static_cast<std::size_t>(cell)]; },
      rank);
}

RankCells rank_cells(const Tissue& tissue, int parts, const PartOfCell& part_of, int rank) {
  if (rank < 0 || rank >= parts)
    throw std::invalid_argument("rank " + std::to_string(rank) + " out of range: the partition has " +
                                std::to_string(parts) + " parts");
  RankCells share;
  share.rank = rank;
  // (A tissue holding part of its cells holds its own.)
  if (tissue.cells_partial()) {
    for (const CellCentre& held : tissue.held_cells())
      if (part_of(held.cell) == rank) share.owned.push_back(held.cell);
  } else {
    for (int cell = 0; cell < static_cast<int>(tissue.cell_count()); ++cell)
      if (part_of(cell) == rank) share.owned.push_back(cell);
  }
  std::map<int, HaloNeighbour> by_rank;  // ordered: neighbours come out by increasing rank
  for (const auto& edge : tissue.cell_edges) {
    const int part_a = part_of(edge.first), part_b = part_of(edge.second);
    if (part_a == part_b || (part_a != rank && part_b != rank)) continue;
    const bool first_is_ours = part_a == rank;
    const int ours = first_is_ours ? edge.first : edge.second;
    const int theirs = first_is_ours ? edge.second : edge.first;
    HaloNeighbour& n = by_rank[first_is_ours ? part_b : part_a];
    n.send.push_back(ours);
    n.receive.push_back(theirs);
  }
  for (auto& entry : by_rank) {
    HaloNeighbour& n = entry.second;
    n.rank = entry.first;
    sort_unique(n.send);
    sort_unique(n.receive);
    share.ghosts.insert(share.ghosts.end(), n.receive.begin(), n.receive.end());
    share.neighbours.push_back(std::move(n));
  }
  sort_unique(share.ghosts);  // (each ghost belongs to one rank: no duplicates; sorted across ranks)
  return share;
}

}  // namespace fibrodem
