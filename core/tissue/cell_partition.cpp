#include "tissue/cell_partition.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "tissue/graph_partitioner.hpp"

namespace fibrodem {

namespace {

// The cell graph in compressed rows, each edge in both directions (Scotch's
// symmetric graph without loops; cell_edges are unique with i < j).
CompressedGraph compressed_graph(const Tissue& tissue) {
  const std::size_t n = tissue.cell_count();
  CompressedGraph g;
  g.row_start.assign(n + 1, 0);
  for (const auto& edge : tissue.cell_edges) {
    ++g.row_start[static_cast<std::size_t>(edge.first) + 1];
    ++g.row_start[static_cast<std::size_t>(edge.second) + 1];
  }
  for (std::size_t cell = 0; cell < n; ++cell) g.row_start[cell + 1] += g.row_start[cell];
  g.neighbours.resize(static_cast<std::size_t>(g.row_start[n]));
  std::vector<int> next(g.row_start.begin(), g.row_start.end() - 1);
  for (const auto& edge : tissue.cell_edges) {
    g.neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(edge.first)]++)] = edge.second;
    g.neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(edge.second)]++)] = edge.first;
  }
  return g;
}

}  // namespace

std::vector<std::size_t> CellPartition::sizes() const {
  std::vector<std::size_t> count(static_cast<std::size_t>(parts), 0);
  for (int part : part_of) ++count[static_cast<std::size_t>(part)];
  return count;
}

std::vector<int> CellPartition::cells_of(int part) const {
  std::vector<int> cells;
  for (std::size_t cell = 0; cell < part_of.size(); ++cell)
    if (part_of[cell] == part) cells.push_back(static_cast<int>(cell));
  return cells;
}

std::size_t CellPartition::cut_edges(const Tissue& tissue) const {
  std::size_t cut = 0;
  for (const auto& edge : tissue.cell_edges)
    cut += part_of[static_cast<std::size_t>(edge.first)] != part_of[static_cast<std::size_t>(edge.second)];
  return cut;
}

CellPitch cell_pitch(const Tissue& tissue) {
  double sum_x_um = 0, sum_y_um = 0;
  for (const auto& [a, b] : tissue.cell_edges) {
    sum_x_um += std::abs(tissue.x_um[static_cast<std::size_t>(a)] - tissue.x_um[static_cast<std::size_t>(b)]);
    sum_y_um += std::abs(tissue.y_um[static_cast<std::size_t>(a)] - tissue.y_um[static_cast<std::size_t>(b)]);
  }
  const auto edges = static_cast<double>(tissue.cell_edges.size());
  CellPitch pitch;
  if (sum_x_um > 0) pitch.x_um = sum_x_um / edges;
  if (sum_y_um > 0) pitch.y_um = sum_y_um / edges;
  return pitch;
}

CellPartition partition_cells(const Tissue& tissue, int parts, PartitionMethod method) {
  const std::size_t n = tissue.cell_count();
  if (parts < 1 || static_cast<std::size_t>(parts) > n)
    throw std::invalid_argument("cannot split " + std::to_string(n) + " cells into " + std::to_string(parts) +
                                " parts: expected 1 to " + std::to_string(n) + " parts (one per MPI rank)");
  CellPartition partition;
  partition.parts = parts;
  partition.part_of.assign(n, 0);
  if (parts == 1) return partition;

  if (method == PartitionMethod::scotch) {
    partition.part_of = split_graph(compressed_graph(tissue), parts, kPartImbalance);
  } else {
    if (tissue.centres_released())
      throw std::logic_error(
          "partition_cells: rcb needs the cells' centres, which this tissue does not hold (freed, or never "
          "given); scotch cuts the cell graph alone");
    partition.part_of = bisect_coordinates(tissue.x_um, tissue.y_um, cell_pitch(tissue), parts);
  }
  return partition;
}

}  // namespace fibrodem
