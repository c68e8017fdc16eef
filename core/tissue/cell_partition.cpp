#include "tissue/cell_partition.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
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

std::size_t CellPartition::cut_edges(const Tissue& tissue) const {
  std::size_t cut = 0;
  for (const auto& edge : tissue.cell_edges)
    cut += part_of[static_cast<std::size_t>(edge.first)] != part_of[static_cast<std::size_t>(edge.second)];
  return cut;
}

namespace {

// cell_pitch's sums, edge by edge in the graph's order (so that a graph
// given edge by edge sums the same bits as the whole graph held).
class PitchSum {
 public:
  void add(const CellCentre& a, const CellCentre& b) {
    sum_x_um_ += std::abs(a.x_um - b.x_um);
    sum_y_um_ += std::abs(a.y_um - b.y_um);
    ++edges_;
  }
  CellPitch pitch() const {
    CellPitch pitch;
    if (sum_x_um_ > 0) pitch.x_um = sum_x_um_ / static_cast<double>(edges_);
    if (sum_y_um_ > 0) pitch.y_um = sum_y_um_ / static_cast<double>(edges_);
    return pitch;
  }

 private:
  double sum_x_um_ = 0, sum_y_um_ = 0;
  std::size_t edges_ = 0;
};

void check_parts(std::size_t n, int parts) {
  if (parts < 1 || static_cast<std::size_t>(parts) > n)
    throw std::invalid_argument("cannot split " + std::to_string(n) + " cells into " + std::to_string(parts) +
                                " parts: expected 1 to " + std::to_string(n) + " parts (one per MPI rank)");
}

void check_centres(const Tissue& tissue) {
  if (tissue.centres_released())
    throw std::logic_error(
        "rcb needs the cells' centres, which this tissue does not hold (freed, or never given); scotch cuts the "
        "cell graph alone");
}

// rcb's cuts with the given pitch, or the tissue's whole graph's.
CoordinateCuts rcb_cuts(const Tissue& tissue, int parts, const CellPitch* pitch) {
  check_centres(tissue);  // (before the pitch, which reads the centres)
  if (!pitch && tissue.graph_partial())
    throw std::logic_error("partition_cells: rcb's pitch is the whole graph's, which this tissue holds part of");
  return cut_by_centres(tissue, parts, pitch ? *pitch : cell_pitch(tissue));
}

}  // namespace

CellPitch cell_pitch(const Tissue& tissue) {
  PitchSum sum;
  for (const auto& [a, b] : tissue.cell_edges) sum.add(tissue.centre_of(a), tissue.centre_of(b));
  return sum.pitch();
}

CellPartition partition_cells(const Tissue& tissue, int parts, PartitionMethod method, const CellPitch* pitch) {
  const std::size_t n = tissue.cell_count();
  check_parts(n, parts);
  CellPartition partition;
  partition.parts = parts;
  partition.part_of.assign(n, 0);
  if (parts == 1) return partition;

  if (method == PartitionMethod::scotch) {
    if (tissue.graph_partial())
      throw std::logic_error("partition_cells: Scotch cuts the whole cell graph, which this tissue holds part of");
    partition.part_of = split_graph(compressed_graph(tissue), parts, kPartImbalance);
  } else {
    const CoordinateCuts cuts = rcb_cuts(tissue, parts, pitch);
    tissue.for_each_centre([&](int cell, double x_um, double y_um) {
      partition.part_of[static_cast<std::size_t>(cell)] = cuts.part_of(cell, x_um, y_um);
    });
  }
  return partition;
}

PartOfCell part_of_cells(const Tissue& tissue, int parts, PartitionMethod method, const CellPitch* pitch) {
  if (method == PartitionMethod::rcb && parts > 1) {
    auto cuts = std::make_shared<const CoordinateCuts>(rcb_cuts(tissue, parts, pitch));
    return [cuts, &tissue](int cell) { return part_by_cuts(*cuts, tissue, cell); };
  }
  auto part_of = std::make_shared<const std::vector<int>>(partition_cells(tissue, parts, method, pitch).part_of);
  return [part_of](int cell) { return (*part_of)[static_cast<std::size_t>(cell)]; };
}

CoordinateCuts cut_by_centres(const Tissue& tissue, int parts, CellPitch pitch) {
  check_centres(tissue);
  check_parts(tissue.cell_count(), parts);
  return CoordinateCuts(
      tissue.cell_count(), parts, pitch,
      [&tissue](const std::function<void(int, double, double)>& visit) { tissue.for_each_centre(visit); });
}

int part_by_cuts(const CoordinateCuts& cuts, const Tissue& tissue, int cell) {
  const CellCentre c = tissue.centre_of(cell);
  return cuts.part_of(cell, c.x_um, c.y_um);
}

PartialGraphCut cut_without_graph(Tissue& tissue, int parts, int rank, std::shared_ptr<const CellStream> cells,
                                  const VisitCellEdge& every_edge) {
  check_parts(tissue.cell_count(), parts);
  PitchSum sum;
  std::pair<int, int> last{-1, -1};
  cells->for_each_edge([&](const CellCentre& a, const CellCentre& b) {
    if (!(a.cell < b.cell && std::pair(a.cell, b.cell) > last))
      throw std::logic_error("cut_without_graph: the tissue's edges do not come in increasing order");
    last = {a.cell, b.cell};
    sum.add(a, b);
  });
  PartialGraphCut cut{
      CoordinateCuts(tissue.cell_count(), parts, sum.pitch(),
                     [&cells](const std::function<void(int, double, double)>& visit) {
                       cells->for_each_cell([&visit](int cell, CellType, double x, double y) { visit(cell, x, y); });
                     }),
      sum.pitch()};
  // The own cells' centres, then the ghosts' (each edge's end on another
  // rank), as the edges at own cells go by.
  std::vector<CellCentre> held;
  cells->for_each_cell([&](int cell, CellType, double x_um, double y_um) {
    if (cut.cuts.part_of(cell, x_um, y_um) == rank) held.push_back({cell, x_um, y_um});
  });
  const std::size_t own = held.size();
  std::vector<std::pair<int, int>> kept;
  std::size_t edges = 0;
  int a_before = -1, part_a = -1;  // (the edges come by their first cell: its part found once)
  cells->for_each_edge([&](const CellCentre& a, const CellCentre& b) {
    if (every_edge) every_edge(a, b);
    ++edges;
    if (a.cell != a_before) part_a = cut.cuts.part_of(a.cell, a.x_um, a.y_um), a_before = a.cell;
    const int part_b = cut.cuts.part_of(b.cell, b.x_um, b.y_um);
    cut.cut_edges += part_a != part_b;
    if (part_a != rank && part_b != rank) return;
    kept.emplace_back(a.cell, b.cell);
    if (part_a != part_b) held.push_back(part_a == rank ? b : a);
  });
  kept.shrink_to_fit();
  const auto by_cell = [](const CellCentre& p, const CellCentre& q) { return p.cell < q.cell; };
  const auto ghosts = held.begin() + static_cast<std::ptrdiff_t>(own);
  std::sort(ghosts, held.end(), by_cell);
  held.erase(std::unique(ghosts, held.end(), [](const CellCentre& p, const CellCentre& q) { return p.cell == q.cell; }),
             held.end());
  std::inplace_merge(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(own), held.end(), by_cell);
  tissue.keep_part_of_graph(std::move(kept), edges);
  tissue.hold_cells_of(std::move(held), std::move(cells));
  return cut;
}

}  // namespace fibrodem
