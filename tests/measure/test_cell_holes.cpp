// Holes of the cell triangulation and the phase singularities they hold: a
// rotor anchored on a region without cells. Each expected number follows from
// the geometry of the test grids (spacing h) or from the phase fields' own
// winding, stated beside it.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "measure/cell_holes.hpp"
#include "measure/cell_triangles.hpp"
#include "measure/phase_singularities.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double h = 100;  // um between neighbouring cells of the test grids

// An n x n square grid of 4-neighbours, without the cells for which `empty`
// holds (their slots are left without a cell).
Tissue grid_without(int n, const std::function<bool(int i, int j)>& empty) {
  Tissue t;
  std::vector<int> id(n * n, -1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (!empty(i, j)) id[j * n + i] = t.add_cell(CellType::myocyte, i * h, j * h);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id[j * n + i];
      if (a < 0) continue;
      if (i + 1 < n && id[j * n + i + 1] >= 0) t.cell_edges.emplace_back(a, id[j * n + i + 1]);
      if (j + 1 < n && id[(j + 1) * n + i] >= 0) t.cell_edges.emplace_back(a, id[(j + 1) * n + i]);
    }
  t.finalise();
  return t;
}

// Every cell of an n x n grid, with the two triangles of each square that
// `filled` keeps (counter-clockwise), but no edges: the triangles are given.
struct Mesh {
  Tissue tissue;
  std::vector<std::array<int, 3>> triangles;
};
Mesh squares(int n, const std::function<bool(int i, int j)>& filled) {
  Mesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.tissue.add_cell(CellType::myocyte, i * h, j * h);
  m.tissue.finalise();
  auto at = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      if (!filled(i, j)) continue;
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

std::vector<double> field(const Tissue& t, const std::function<double(double x_um, double y_um)>& phase) {
  std::vector<double> p(t.cell_count());
  for (std::size_t c = 0; c < p.size(); ++c) p[c] = wrap_phase(phase(t.x_um[c], t.y_um[c]));
  return p;
}

// A spiral turning about (x0, y0) [um]: charge +1 around it.
std::function<double(double, double)> spiral(double x0, double y0) {
  return [=](double x, double y) { return std::atan2(y - y0, x - x0) - 0.7; };
}

// A 15 x 15 grid without the cells of columns and rows 4-8 (a 5 x 5 block).
bool block_4_to_8(int i, int j) { return i >= 4 && i <= 8 && j >= 4 && j <= 8; }
}  // namespace

TEST_CASE("a block without cells is one hole, its rim through the cells around it") {
  // The rim runs through columns and rows 3 and 9: a 6h x 6h square centred
  // at (6h, 6h). The sheet's outer rim (counter-clockwise) is no hole.
  const Tissue t = grid_without(15, block_4_to_8);
  const auto holes = cell_holes(t, cell_triangles(t));
  REQUIRE(holes.size() == 1);
  CHECK(holes[0].rim.size() == 24);
  CHECK(holes[0].area_mm2 == doctest::Approx(0.36));
  CHECK(holes[0].x_mm == doctest::Approx(0.6));
  CHECK(holes[0].y_mm == doctest::Approx(0.6));
  CHECK(holes[0].reach_mm == doctest::Approx(0.3 * std::sqrt(2.0)));  // to a corner of the rim
  CHECK(holes[0].islands.empty());
  const Tissue whole = grid_without(15, [](int, int) { return false; });
  CHECK(cell_holes(whole, cell_triangles(whole)).empty());
}

TEST_CASE("a rotor turning around a hole has its phase singularity there, at the hole's centroid") {
  // The spiral's centre is in the block, off the hole's centroid: no
  // triangle has a charge, the hole has +1 (or -1 turning the other way).
  const Tissue t = grid_without(15, block_4_to_8);
  const auto triangles = cell_triangles(t);
  const auto holes = cell_holes(t, triangles);
  for (int sense : {1, -1}) {
    CAPTURE(sense);
    const auto ps = find_phase_singularities(
        t, triangles, field(t, [&](double x, double y) { return sense * spiral(520, 710)(x, y); }), holes);
    REQUIRE(ps.size() == 1);
    CHECK(ps[0].hole == 0);
    CHECK(ps[0].triangle == -1);
    CHECK(ps[0].chirality == sense);
    CHECK(ps[0].x_mm == doctest::Approx(0.6));
    CHECK(ps[0].y_mm == doctest::Approx(0.6));
    const auto around = cells_around(ps[0], triangles, holes);
    CHECK(std::vector<int>(around.begin(), around.end()) == holes[0].rim);
  }
  SUBCASE("a planar wave passing the hole has no phase singularity") {
    const double k = 2 * kPi / 1000;
    CHECK(find_phase_singularities(t, triangles, field(t, [&](double x, double y) { return k * (0.8 * x - 0.6 * y); }),
                                   holes)
              .empty());
  }
  SUBCASE("a rotor beside the hole is on a triangle, the hole holds nothing") {
    const auto ps = find_phase_singularities(t, triangles, field(t, spiral(1150, 1230)), holes);
    REQUIRE(ps.size() == 1);
    CHECK(ps[0].triangle >= 0);
    CHECK(ps[0].hole == -1);
  }
}

TEST_CASE("the charges of triangles and holes add up to the winding around the sheet's edge") {
  // Any phase field: each inner side is walked once each way, so the sum of
  // the charges is the charge of the outer rim (the grid's edge cells,
  // counter-clockwise). Random phases give many charges of both signs.
  const int n = 15;
  const Tissue t = grid_without(n, block_4_to_8);
  const auto triangles = cell_triangles(t);
  const auto holes = cell_holes(t, triangles);
  std::vector<int> edge;  // the grid's edge cells, counter-clockwise
  auto id = [&](int i, int j) {
    for (std::size_t c = 0; c < t.cell_count(); ++c)
      if (t.x_um[c] == i * h && t.y_um[c] == j * h) return static_cast<int>(c);
    return -1;
  };
  for (int i = 0; i < n - 1; ++i) edge.push_back(id(i, 0));
  for (int j = 0; j < n - 1; ++j) edge.push_back(id(n - 1, j));
  for (int i = n - 1; i > 0; --i) edge.push_back(id(i, n - 1));
  for (int j = n - 1; j > 0; --j) edge.push_back(id(0, j));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-kPi, kPi);
  int hole_charges = 0;
  for (int draw = 0; draw < 20; ++draw) {
    std::vector<double> phase(t.cell_count());
    for (auto& p : phase) p = uniform(rng);
    int sum = 0;
    for (const auto& ps : find_phase_singularities(t, triangles, phase, holes)) {
      sum += ps.chirality;
      if (ps.hole >= 0) ++hole_charges;
    }
    CHECK(sum == loop_charge(edge, phase));
  }
  CHECK(hole_charges > 0);  // the hole took part: a 24-cell rim of random phases winds often
}

TEST_CASE("an island inside a hole carries its own charge, which the hole does not count again") {
  // The block of columns and rows 3-11 is empty but for a 2 x 2 island at
  // 6-7 (one square: two triangles). A rotor about the island's square is on
  // its triangles; one elsewhere in the block is the hole's.
  const Tissue t = grid_without(15, [](int i, int j) {
    const bool block = i >= 3 && i <= 11 && j >= 3 && j <= 11;
    const bool island = i >= 6 && i <= 7 && j >= 6 && j <= 7;
    return block && !island;
  });
  const auto triangles = cell_triangles(t);
  const auto holes = cell_holes(t, triangles);
  REQUIRE(holes.size() == 1);
  CHECK(holes[0].islands.size() == 1);
  CHECK(holes[0].area_mm2 == doctest::Approx(1.0));  // the rim: columns and rows 2 and 12

  auto on_island = find_phase_singularities(t, triangles, field(t, spiral(655, 640)), holes);
  REQUIRE(on_island.size() == 1);
  CHECK(on_island[0].triangle >= 0);
  auto in_hole = find_phase_singularities(t, triangles, field(t, spiral(420, 930)), holes);
  REQUIRE(in_hole.size() == 1);
  CHECK(in_hole[0].hole == 0);
}

TEST_CASE("rims that touch at one cell are walked apart") {
  // Squares of a 6 x 6 cell mesh; each missing square is a hole of area h^2
  // centred on it, unless it is on the mesh's edge (then it is outside).
  auto hole_centres = [](const Mesh& m) {
    std::vector<std::array<double, 3>> found;
    for (const auto& hole : cell_holes(m.tissue, m.triangles)) found.push_back({hole.x_mm, hole.y_mm, hole.area_mm2});
    std::sort(found.begin(), found.end());
    return found;
  };
  SUBCASE("two holes meeting at a corner") {
    const auto found =
        hole_centres(squares(6, [](int i, int j) { return !((i == 1 && j == 1) || (i == 2 && j == 2)); }));
    REQUIRE(found.size() == 2);
    CHECK(found[0][0] == doctest::Approx(0.15));
    CHECK(found[0][1] == doctest::Approx(0.15));
    CHECK(found[0][2] == doctest::Approx(0.01));
    CHECK(found[1][0] == doctest::Approx(0.25));
    CHECK(found[1][1] == doctest::Approx(0.25));
    CHECK(found[1][2] == doctest::Approx(0.01));
  }
  SUBCASE("a hole meeting a notch of the edge at a corner") {
    const auto found =
        hole_centres(squares(6, [](int i, int j) { return !((i == 0 && j == 0) || (i == 1 && j == 1)); }));
    REQUIRE(found.size() == 1);
    CHECK(found[0][0] == doctest::Approx(0.15));
    CHECK(found[0][1] == doctest::Approx(0.15));
    CHECK(found[0][2] == doctest::Approx(0.01));
  }
  SUBCASE("two meshes meeting at a corner have no hole") {
    CHECK(hole_centres(squares(6, [](int i, int j) {
            return (i < 2 && j < 2) || (i >= 2 && j >= 2 && i < 4 && j < 4);
          })).empty());
  }
}

TEST_CASE("a rotor turning around a compact scar of a fibrotic sheet is found at the scar") {
  // A 5 x 5 mm sheet of staggered myocyte columns with a compact collagen
  // region (no cells) of 0.08 x 25 mm^2 = 2 mm^2, aspect 2 (1 mm across
  // the fibres, 2 mm along), centred: a spiral about a point in it is one PS, at the centroid of the
  // hole, which is the region's centre within a cell (125 um along the
  // fibres, columns ~24 um apart).
  const Tissue t = testing::build_tissue(
      {{"builder", "fibrotic_sheet"},
       {"width_mm", 5},
       {"length_mm", 5},
       {"fibrosis", {{"pattern", "compact"}, {"as", "collagen"}, {"density", 0.08}, {"aspect", 2}}}});
  const Tissue whole = testing::build_tissue({{"builder", "fibrotic_sheet"}, {"width_mm", 5}, {"length_mm", 5}});
  CHECK(cell_holes(whole, cell_triangles(whole)).empty());  // its staggered edges enclose nothing
  const auto triangles = cell_triangles(t);
  const auto holes = cell_holes(t, triangles);
  REQUIRE(holes.size() == 1);
  // The rim runs through the centres of the cells next to the region: it
  // encloses more than the region (2 mm^2), less than the region grown by a
  // slot on every side ((1 + 2 x 0.024) x (2 + 2 x 0.125) = 2.36 mm^2).
  CHECK(holes[0].area_mm2 > 2.0);
  CHECK(holes[0].area_mm2 < 2.36);
  const auto ps = find_phase_singularities(t, triangles, field(t, spiral(2300, 2800)), holes);
  REQUIRE(ps.size() == 1);
  CHECK(ps[0].hole == 0);
  CHECK(std::abs(ps[0].x_mm - 2.5) < 0.125);
  CHECK(std::abs(ps[0].y_mm - 2.5) < 0.125);
}
