// The cells split over ranks (tissue/cell_partition.hpp), by coordinate
// bisection and by Scotch: every cell in one part, balanced, deterministic,
// and far fewer cut edges than a random split, on a grid whose best cuts are
// known and on a built tissue.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>

#include "support/scenes.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/cell_partition.hpp"
#include "tissue/rank_cells.hpp"
#include "tissue/tissue_builder.hpp"

using namespace fibrodem;

namespace {

// columns x rows cells, each joined to its 4 neighbours.
Tissue grid_tissue(int columns, int rows) {
  Tissue t;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      t.type.push_back(CellType::myocyte);
      t.x_um.push_back(25.0 * c);
      t.y_um.push_back(125.0 * r);
    }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const int cell = r * columns + c;
      if (c + 1 < columns) t.cell_edges.emplace_back(cell, cell + 1);
      if (r + 1 < rows) t.cell_edges.emplace_back(cell, cell + columns);
    }
  std::sort(t.cell_edges.begin(), t.cell_edges.end());
  return t;
}

Tissue built_tissue() {
  const json spec = {{"builder", "in_series"}, {"width_mm", 0.6}, {"height_mm", 1.2}, {"fm_ratio", 0.3}};
  JsonReader reader(spec, "tissue");
  return make_tissue_builder(reader)->build(7);
}

// Cut edges of a uniformly random assignment of cells to parts.
std::size_t random_cut(const Tissue& tissue, int parts) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> pick(0, parts - 1);
  CellPartition p;
  p.parts = parts;
  for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell) p.part_of.push_back(pick(random));
  return p.cut_edges(tissue);
}

void check_is_partition(const CellPartition& p, const Tissue& tissue, int parts) {
  REQUIRE(p.parts == parts);
  REQUIRE(p.part_of.size() == tissue.cell_count());
  for (int part : p.part_of) REQUIRE((part >= 0 && part < parts));
  const std::vector<std::size_t> sizes = p.sizes();
  CHECK(std::all_of(sizes.begin(), sizes.end(), [](std::size_t size) { return size > 0; }));
}

// The cells of part p, in increasing order.
std::vector<int> cells_of(const CellPartition& p, int part) {
  std::vector<int> cells;
  for (std::size_t cell = 0; cell < p.part_of.size(); ++cell)
    if (p.part_of[cell] == part) cells.push_back(static_cast<int>(cell));
  return cells;
}

// Each cell's part by CoordinateCuts, the cells handed over last first.
std::vector<int> parts_by_cuts(const std::vector<double>& x_um, const std::vector<double>& y_um, CellPitch pitch,
                               int parts, std::size_t collect_budget = CoordinateCuts::kCollectBudget) {
  const std::size_t n = x_um.size();
  const CoordinateCuts cuts(
      n, parts, pitch,
      [&](const std::function<void(int, double, double)>& visit) {
        for (std::size_t i = n; i-- > 0;) visit(static_cast<int>(i), x_um[i], y_um[i]);
      },
      collect_budget);
  std::vector<int> part_of(n);
  for (std::size_t i = 0; i < n; ++i) part_of[i] = cuts.part_of(static_cast<int>(i), x_um[i], y_um[i]);
  return part_of;
}

// Recursive coordinate bisection as its definition reads, by sorting: the
// cells of a box sorted by (coordinate along its longer side in cells,
// number), the first as many as its lower half of parts holds go there.
void bisect_by_sorting(const std::vector<double>& x_um, const std::vector<double>& y_um, CellPitch pitch,
                       std::vector<int> cells, int first_part, int parts, std::size_t n_all, int parts_all,
                       std::vector<int>& part_of) {
  if (parts == 1) {
    for (int cell : cells) part_of[static_cast<std::size_t>(cell)] = first_part;
    return;
  }
  const auto extent = [&](const std::vector<double>& v) {
    const auto [low, high] = std::minmax_element(cells.begin(), cells.end(), [&](int a, int b) { return v[a] < v[b]; });
    return v[static_cast<std::size_t>(*high)] - v[static_cast<std::size_t>(*low)];
  };
  const std::vector<double>& along = extent(x_um) / pitch.x_um >= extent(y_um) / pitch.y_um ? x_um : y_um;
  std::sort(cells.begin(), cells.end(), [&](int a, int b) { return std::pair(along[a], a) < std::pair(along[b], b); });
  const int lower_parts = parts / 2;
  std::size_t lower = 0;
  for (int p = first_part; p < first_part + lower_parts; ++p)
    lower += n_all / parts_all + (static_cast<std::size_t>(p) < n_all % parts_all ? 1 : 0);
  const auto middle = cells.begin() + static_cast<std::ptrdiff_t>(lower);
  bisect_by_sorting(x_um, y_um, pitch, {cells.begin(), middle}, first_part, lower_parts, n_all, parts_all, part_of);
  bisect_by_sorting(x_um, y_um, pitch, {middle, cells.end()}, first_part + lower_parts, parts - lower_parts, n_all,
                    parts_all, part_of);
}

// No part above (1 + kPartImbalance) times the mean, rounded up to whole cells.
void check_balanced(const CellPartition& p) {
  const std::vector<std::size_t> sizes = p.sizes();
  std::size_t total = 0;
  for (std::size_t size : sizes) total += size;
  const double mean = static_cast<double>(total) / p.parts;
  const auto largest = static_cast<double>(*std::max_element(sizes.begin(), sizes.end()));
  CHECK(largest <= std::ceil((1 + kPartImbalance) * mean));
}

}  // namespace

const PartitionMethod kMethods[] = {PartitionMethod::rcb, PartitionMethod::scotch};

TEST_CASE("cell partition: a 40 x 30 grid in 2 and 4 parts, balanced, with near-minimal cuts") {
  const Tissue grid = grid_tissue(40, 30);
  // The smallest bisection of a 40 x 30 grid cuts the 30 edges of one row
  // of columns; four equal quadrants cut 30 + 40 = 70. Scotch's multilevel
  // heuristic is not exact: within twice these.
  const int best_cut[] = {0, 0, 30, 0, 70};
  for (PartitionMethod method : kMethods)
    for (int parts : {2, 4}) {
      CAPTURE(static_cast<int>(method));
      CAPTURE(parts);
      const CellPartition p = partition_cells(grid, parts, method);
      check_is_partition(p, grid, parts);
      check_balanced(p);
      CHECK(p.cut_edges(grid) <= static_cast<std::size_t>(2 * best_cut[parts]));
      // A random split cuts about (1 - 1/parts) of the 2330 edges.
      CHECK(p.cut_edges(grid) * 10 < random_cut(grid, parts));
    }
}

// The grid's cells are 25 um apart along x and 125 um along y: 1 mm by
// 3.6 mm, but 40 by 30 cells. Cut across its longer side in um, along y, a
// bisection would cut 40 edges; measured in cells it cuts the 30 of one
// column exactly, and the quadrants the 70 of the best cut.
TEST_CASE("coordinate bisection: parts within one cell of each other, cut across the side longer in cells") {
  const Tissue grid = grid_tissue(40, 30);
  const CellPitch pitch = cell_pitch(grid);
  CHECK(pitch.y_um / pitch.x_um == doctest::Approx(125.0 / 25.0).epsilon(0.03));
  CHECK(partition_cells(grid, 2).cut_edges(grid) == 30);
  CHECK(partition_cells(grid, 4).cut_edges(grid) == 70);
  // 1,200 cells in 7 parts: 172 in the first three (1,200 % 7 = 3), 171 in the rest.
  const CellPartition seven = partition_cells(grid, 7);
  check_is_partition(seven, grid, 7);
  CHECK(seven.sizes() == std::vector<std::size_t>{172, 172, 172, 171, 171, 171, 171});
}

TEST_CASE("coordinate bisection: a function of the centres alone, whatever their graph") {
  const Tissue tissue = built_tissue();
  Tissue without_graph = tissue;
  without_graph.cell_edges.clear();
  // Without edges the pitch is 1 um both ways; with the same pitch the
  // parts are the same cells.
  CHECK(parts_by_cuts(tissue.x_um, tissue.y_um, cell_pitch(tissue), 3) ==
        parts_by_cuts(without_graph.x_um, without_graph.y_um, cell_pitch(tissue), 3));
  CHECK(partition_cells(tissue, 3).part_of == parts_by_cuts(tissue.x_um, tissue.y_um, cell_pitch(tissue), 3));
  // Cells on one point: split by cell number, lower numbers first.
  const std::vector<double> same(10, 5.0);
  CHECK(parts_by_cuts(same, same, CellPitch{}, 3) == std::vector<int>{0, 0, 0, 0, 1, 1, 1, 2, 2, 2});
  // A tissue without centres cannot be cut by them.
  Tissue graph_only;
  graph_only.type.assign(4, CellType::myocyte);
  graph_only.cell_edges = {{0, 1}, {1, 2}, {2, 3}};
  CHECK_THROWS_AS(partition_cells(graph_only, 2, PartitionMethod::rcb), std::logic_error);
  CHECK(partition_cells(graph_only, 2, PartitionMethod::scotch).cut_edges(graph_only) == 1);
}

TEST_CASE("coordinate cuts: the parts of bisection by sorting, whatever the cells' order and the memory held") {
  // Random centres on a coarse lattice (many cells share a coordinate, some
  // a centre), on a line, and spread: the cuts, found in passes over the
  // cells handed over last first, narrowing each median through histograms
  // when it may collect few cells at once, give each cell the part that
  // sorting every box gives.
  std::mt19937_64 random(2021);
  for (int shape = 0; shape < 3; ++shape)
    for (const std::size_t n : {std::size_t{1}, std::size_t{37}, std::size_t{1000}, std::size_t{20000}}) {
      std::vector<double> x(n), y(n);
      for (std::size_t i = 0; i < n; ++i) {
        x[i] = shape == 1   ? 1.0
               : shape == 0 ? 23.57 * static_cast<double>(random() % 9)
                            : std::ldexp(random() >> 11, -40);
        y[i] = shape == 2 ? std::ldexp(random() >> 11, -53) : 125.0 * static_cast<double>(random() % 13);
      }
      for (const int parts : {1, 2, 3, 7, 16})
        for (const std::size_t budget : {std::size_t{16}, std::size_t{500}, CoordinateCuts::kCollectBudget}) {
          if (static_cast<std::size_t>(parts) > n) continue;
          CAPTURE(shape);
          CAPTURE(n);
          CAPTURE(parts);
          CAPTURE(budget);
          const CellPitch pitch{23.57, 125};
          std::vector<int> expected(n), cells(n);
          for (std::size_t i = 0; i < n; ++i) cells[i] = static_cast<int>(i);
          bisect_by_sorting(x, y, pitch, cells, 0, parts, n, parts, expected);
          CHECK(parts_by_cuts(x, y, pitch, parts, budget) == expected);
        }
    }
}

TEST_CASE("coordinate cuts: cells that change between passes are refused") {
  int calls = 0;
  const auto fewer_each_time = [&calls](const std::function<void(int, double, double)>& visit) {
    const int n = 100 - calls++;
    for (int cell = 0; cell < n; ++cell) visit(cell, cell, 0);
  };
  CHECK_THROWS_AS(CoordinateCuts(100, 2, CellPitch{}, fewer_each_time), std::logic_error);
  CHECK_THROWS_AS(CoordinateCuts(3, 4, CellPitch{}, fewer_each_time), std::invalid_argument);
}

TEST_CASE("cell partition: a built tissue with fibroblasts, 2 to 4 parts") {
  const Tissue tissue = built_tissue();
  REQUIRE(tissue.count(CellType::fibroblast) > 0);
  for (PartitionMethod method : kMethods)
    for (int parts : {2, 3, 4}) {
      CAPTURE(static_cast<int>(method));
      CAPTURE(parts);
      const CellPartition p = partition_cells(tissue, parts, method);
      check_is_partition(p, tissue, parts);
      check_balanced(p);
      CHECK(p.cut_edges(tissue) * 5 < random_cut(tissue, parts));
    }
}

TEST_CASE("cell partition: the same tissue gives the same parts") {
  const Tissue tissue = built_tissue();
  for (PartitionMethod method : kMethods) {
    CAPTURE(static_cast<int>(method));
    const CellPartition first = partition_cells(tissue, 3, method);
    // In between, a partition of another graph (Scotch's state must not leak).
    (void)partition_cells(grid_tissue(20, 20), 4, method);
    const CellPartition again = partition_cells(built_tissue(), 3, method);
    CHECK(first.part_of == again.part_of);
  }
}

TEST_CASE("cell partition: one part without a cut, and a part count out of range refused") {
  const Tissue grid = grid_tissue(3, 2);
  for (PartitionMethod method : kMethods) {
    CAPTURE(static_cast<int>(method));
    const CellPartition one = partition_cells(grid, 1, method);
    CHECK(one.part_of == std::vector<int>(6, 0));
    CHECK(one.cut_edges(grid) == 0);
    CHECK_THROWS_WITH_AS(partition_cells(grid, 7, method),
                         "cannot split 6 cells into 7 parts: expected 1 to 6 parts (one per MPI rank)",
                         std::invalid_argument);
    CHECK_THROWS_AS(partition_cells(grid, 0, method), std::invalid_argument);
    // Every cell a part of its own.
    const CellPartition six = partition_cells(grid, 6, method);
    check_is_partition(six, grid, 6);
    CHECK(six.sizes() == std::vector<std::size_t>(6, 1));
  }
}

TEST_CASE("rank cells: ghosts close each rank's coupling, and the ranks agree on every message") {
  const Tissue tissue = built_tissue();
  const int parts = 3;
  const CellPartition p = partition_cells(tissue, parts);
  std::vector<RankCells> shares;
  for (int rank = 0; rank < parts; ++rank) shares.push_back(rank_cells(tissue, p, rank));
  std::size_t owned_total = 0;
  for (const RankCells& share : shares) {
    CAPTURE(share.rank);
    owned_total += share.owned.size();
    CHECK(share.owned == cells_of(p, share.rank));
    // Every neighbour of an owned cell is owned or a ghost; every ghost is
    // another rank's and a neighbour of an owned cell.
    std::vector<char> reachable(tissue.cell_count(), 0);
    for (int cell : share.owned) reachable[static_cast<std::size_t>(cell)] = 1;
    for (int cell : share.ghosts) {
      CHECK(p.part_of[static_cast<std::size_t>(cell)] != share.rank);
      reachable[static_cast<std::size_t>(cell)] = 1;
    }
    std::vector<int> needed;
    for (const auto& edge : tissue.cell_edges) {
      const bool a_ours = p.part_of[static_cast<std::size_t>(edge.first)] == share.rank;
      const bool b_ours = p.part_of[static_cast<std::size_t>(edge.second)] == share.rank;
      if (a_ours) CHECK(reachable[static_cast<std::size_t>(edge.second)]);
      if (b_ours) CHECK(reachable[static_cast<std::size_t>(edge.first)]);
      if (a_ours && !b_ours) needed.push_back(edge.second);
      if (b_ours && !a_ours) needed.push_back(edge.first);
    }
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    CHECK(share.ghosts == needed);
    // What a sends to b is what b receives from a, cell for cell, in order.
    for (const HaloNeighbour& n : share.neighbours) {
      const RankCells& other = shares[static_cast<std::size_t>(n.rank)];
      const auto back = std::find_if(other.neighbours.begin(), other.neighbours.end(),
                                     [&](const HaloNeighbour& m) { return m.rank == share.rank; });
      REQUIRE(back != other.neighbours.end());
      CHECK(back->receive == n.send);
      CHECK(back->send == n.receive);
    }
  }
  CHECK(owned_total == tissue.cell_count());
  // One part: no ghosts, no neighbours.
  const RankCells alone = rank_cells(tissue, partition_cells(tissue, 1), 0);
  CHECK(alone.owned.size() == tissue.cell_count());
  CHECK(alone.ghosts.empty());
  CHECK(alone.neighbours.empty());
  CHECK_THROWS_AS(rank_cells(tissue, p, 3), std::invalid_argument);
}

TEST_CASE("cut without the graph: the whole tissue's partition and cut, the rank's edges and shares") {
  // A rank's tissue built without its graph, the graph given edge by edge:
  // rcb with the whole graph's pitch (the same parts), the whole graph's
  // counts, only the edges with one of its cells at an end, and from those
  // the same share (owned, ghosts, halo) as from the whole tissue.
  const Tissue whole = built_tissue();
  const CellPartition reference = partition_cells(whole, 3);
  for (int rank = 0; rank < 3; ++rank) {
    CAPTURE(rank);
    std::shared_ptr<const CellStream> stream = stream_of(whole);
    Tissue part = stream->cell_types();
    CHECK(part.type == whole.type);
    CHECK(part.centres_released());
    std::size_t seen = 0;
    const PartialGraphCut cut =
        cut_without_graph(part, 3, rank, stream, [&seen](const CellCentre&, const CellCentre&) { ++seen; });
    // Its own cells and ghosts held, with their types and centres (the
    // others' read from the stream), and the counts of the whole tissue.
    CHECK(part.cells_partial());
    CHECK(part.x_um.empty());
    CHECK(part.type.empty());
    CHECK(part.cell_count() == whole.cell_count());
    CHECK(part.count(CellType::myocyte) == whole.count(CellType::myocyte));
    CHECK(part.count(CellType::fibroblast) == whole.count(CellType::fibroblast));
    REQUIRE(whole.count(CellType::fibroblast) > 0);  // (the premise: both types to tell apart)
    std::vector<int> held_cells;
    for (const CellCentre& c : part.held_cells()) {
      held_cells.push_back(c.cell);
      const auto i = static_cast<std::size_t>(c.cell);
      CHECK((c.x_um == whole.x_um[i] && c.y_um == whole.y_um[i]));
      CHECK(part.type_of(c.cell) == whole.type[i]);
    }
    std::vector<int> every_cell(whole.cell_count());
    std::iota(every_cell.begin(), every_cell.end(), 0);
    std::reverse(every_cell.begin(), every_cell.end());  // (asked in any order)
    std::vector<CellType> reversed_types(whole.type.rbegin(), whole.type.rend());
    CHECK(part.types_of(every_cell) == reversed_types);
    std::size_t visited = 0;
    part.for_each_centre([&](int cell, double x_um, double y_um) {
      visited += cell == static_cast<int>(visited) && x_um == whole.x_um[visited] && y_um == whole.y_um[visited];
    });
    CHECK(visited == whole.cell_count());
    for (int cell = 0; cell < static_cast<int>(whole.cell_count()); ++cell) {
      const auto i = static_cast<std::size_t>(cell);
      REQUIRE(cut.cuts.part_of(cell, whole.x_um[i], whole.y_um[i]) == reference.part_of[i]);
    }
    CHECK(cut.pitch.x_um == cell_pitch(whole).x_um);
    CHECK(cut.pitch.y_um == cell_pitch(whole).y_um);
    CHECK(cut.cut_edges == reference.cut_edges(whole));
    CHECK(seen == whole.cell_edges.size());
    CHECK(part.graph_partial());
    CHECK(part.built_cell_edges() == whole.cell_edges.size());
    std::vector<std::pair<int, int>> expected;
    for (const auto& [a, b] : whole.cell_edges)
      if (reference.part_of[static_cast<std::size_t>(a)] == rank ||
          reference.part_of[static_cast<std::size_t>(b)] == rank)
        expected.emplace_back(a, b);
    CHECK(part.cell_edges == expected);
    CHECK(part.cell_edges.size() < whole.cell_edges.size());
    const RankCells from_part = rank_cells(
        part, 3, [&](int cell) { return part_by_cuts(cut.cuts, part, cell); }, rank);
    const RankCells from_whole = rank_cells(whole, reference, rank);
    CHECK(from_part.owned == from_whole.owned);
    CHECK(from_part.ghosts == from_whole.ghosts);
    std::vector<int> own_and_ghosts = from_whole.owned;
    own_and_ghosts.insert(own_and_ghosts.end(), from_whole.ghosts.begin(), from_whole.ghosts.end());
    std::sort(own_and_ghosts.begin(), own_and_ghosts.end());
    CHECK(held_cells == own_and_ghosts);
    REQUIRE(from_part.neighbours.size() == from_whole.neighbours.size());
    for (std::size_t k = 0; k < from_part.neighbours.size(); ++k) {
      CHECK(from_part.neighbours[k].send == from_whole.neighbours[k].send);
      CHECK(from_part.neighbours[k].receive == from_whole.neighbours[k].receive);
    }
    // Cut again (a checkpoint's parts) with the whole graph's pitch: the
    // same parts; without it, refused (the part's pitch is not the whole's).
    CHECK(partition_cells(part, 3, PartitionMethod::rcb, &cut.pitch).part_of == reference.part_of);
    CHECK_THROWS_AS(partition_cells(part, 3), std::logic_error);
    CHECK_THROWS_AS(partition_cells(part, 3, PartitionMethod::scotch), std::logic_error);
    // A centre neither held nor whole is refused; once freed, every centre is.
    const int not_held = [&] {
      for (int cell = 0;; ++cell)
        if (!std::binary_search(held_cells.begin(), held_cells.end(), cell)) return cell;
    }();
    CHECK_THROWS_AS(part.centre_of(not_held), std::logic_error);
    CHECK_THROWS_AS(part.type_of(not_held), std::logic_error);
    part.release_centres();
    CHECK(part.centres_released());
    CHECK_THROWS_AS(part.for_each_centre([](int, double, double) {}), std::logic_error);
    CHECK_THROWS_AS(part.centre_of(held_cells.front()), std::logic_error);
    CHECK_THROWS_AS(part.type_of(held_cells.front()), std::logic_error);
    CHECK(part.cell_count() == whole.cell_count());
    CHECK(part.count(CellType::fibroblast) == whole.count(CellType::fibroblast));
  }
  // Edges out of order (a builder that does not give them sorted) are refused.
  Tissue reversed_graph = whole;
  std::reverse(reversed_graph.cell_edges.begin(), reversed_graph.cell_edges.end());
  std::shared_ptr<const CellStream> reversed = stream_of(reversed_graph);
  Tissue part = reversed->cell_types();
  CHECK_THROWS_AS(cut_without_graph(part, 3, 0, reversed), std::logic_error);
}

TEST_CASE("cell numbering: a rank holds its own cells, then its ghosts, and finds each by tissue number") {
  const Tissue tissue = built_tissue();
  const CellPartition p = partition_cells(tissue, 3);
  for (int rank = 0; rank < 3; ++rank) {
    CAPTURE(rank);
    const RankCells share = rank_cells(tissue, p, rank);
    const CellNumbering numbering(tissue.cell_count(), share);
    REQUIRE(numbering.own() == share.owned.size());
    REQUIRE(numbering.held() == share.owned.size() + share.ghosts.size());
    CHECK(numbering.tissue_cells() == tissue.cell_count());
    // Every tissue cell: held at its place in owned, or after them at its
    // place in ghosts, or not at all.
    for (int cell = 0; cell < static_cast<int>(tissue.cell_count()); ++cell) {
      const auto own = std::find(share.owned.begin(), share.owned.end(), cell);
      const auto ghost = std::find(share.ghosts.begin(), share.ghosts.end(), cell);
      const long expected = own != share.owned.end() ? own - share.owned.begin()
                            : ghost != share.ghosts.end()
                                ? static_cast<long>(share.owned.size()) + (ghost - share.ghosts.begin())
                                : -1;
      CHECK(numbering.held_cell(cell) == expected);
      CHECK(numbering.owns(cell) == (own != share.owned.end()));
      if (expected >= 0) CHECK(numbering.tissue_cell(static_cast<std::size_t>(expected)) == cell);
    }
    CHECK(numbering.held_cell(-1) == -1);
    CHECK(numbering.held_cell(static_cast<long>(tissue.cell_count())) == -1);
    // The halo plan in held numbers: the same cells, each at its held place.
    const RankCells held = numbered_from_ghost(share, numbering.own());
    REQUIRE(held.neighbours.size() == share.neighbours.size());
    for (std::size_t k = 0; k < held.neighbours.size(); ++k) {
      for (std::size_t i = 0; i < held.neighbours[k].send.size(); ++i)
        CHECK(numbering.tissue_cell(static_cast<std::size_t>(held.neighbours[k].send[i])) ==
              share.neighbours[k].send[i]);
      for (std::size_t i = 0; i < held.neighbours[k].receive.size(); ++i)
        CHECK(numbering.tissue_cell(static_cast<std::size_t>(held.neighbours[k].receive[i])) ==
              share.neighbours[k].receive[i]);
    }
  }
  // One process: every cell under its own number.
  const CellNumbering whole(tissue.cell_count());
  CHECK(whole.whole());
  CHECK(whole.held() == tissue.cell_count());
  CHECK(whole.own() == tissue.cell_count());
  CHECK(whole.held_cell(7) == 7);
  CHECK(whole.tissue_cell(7) == 7);
}
