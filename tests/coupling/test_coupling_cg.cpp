// The implicit gap-junction step by conjugate gradients (coupling/coupling_cg.hpp)
// against a direct dense solve of the same system, its failure when it cannot
// converge, and its independence of the thread count.
#include <doctest/doctest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling/coupling_field.hpp"
#include "coupling/gap_junction.hpp"
#include "support/coupling_reference.hpp"

using namespace fibrodem;
using namespace fibrodem::test;

namespace {

// The seed paper's D_m and D_f [nS], the same D_m end to end and side to side.
const JunctionConductances kSeedJunctions{1000.0, 1000.0, 0.3};

// 90 cells of both types on an irregular graph: a chain with random chords
// (degrees 1 to ~6) and one cell with no junction at all.
Tissue irregular_tissue() {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  Tissue tissue;
  const int n = 90;
  for (int i = 0; i < n; ++i)
    tissue.type.push_back(unit(random) < 0.7 ? CellType::myocyte : CellType::fibroblast);
  std::set<std::pair<int, int>> edges;
  for (int i = 0; i + 2 < n; ++i) edges.insert({i, i + 1});  // cell n - 1 stays alone
  std::uniform_int_distribution<int> cell(0, n - 2);
  for (int k = 0; k < 80; ++k) {
    const int a = cell(random), b = cell(random);
    if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
  }
  tissue.cell_edges.assign(edges.begin(), edges.end());
  return tissue;
}

// Capacitances of both kinds of cell (fibroblasts ~6 pF, myocytes ~100 pF).
std::vector<double> capacitances(const Tissue& tissue) {
  std::vector<double> C;
  for (std::size_t i = 0; i < tissue.cell_count(); ++i)
    C.push_back(tissue.type[i] == CellType::myocyte ? 80.0 + 0.5 * static_cast<double>(i % 40)
                                                    : 5.0 + 0.1 * static_cast<double>(i % 10));
  return C;
}

// Potentials of a wavefront: depolarised cells beside resting ones.
std::vector<double> potentials(std::size_t n) {
  std::vector<double> V;
  for (std::size_t i = 0; i < n; ++i) V.push_back(i % 7 < 3 ? 20.0 - static_cast<double>(i % 5) : -84.0 + 0.3 * static_cast<double>(i % 11));
  return V;
}

}  // namespace

TEST_CASE("coupling CG: within its tolerance of a direct solve on an irregular tissue, at steps 0.001 to 10 ms") {
  const Tissue tissue = irregular_tissue();
  const auto C = capacitances(tissue);
  GapJunctionCoupler coupler(tissue, kSeedJunctions, C);
  const auto V = potentials(tissue.cell_count());
  for (double dt_ms : {0.001, 0.01, 0.1, 1.0, 10.0}) {
    for (double tolerance_mV : {1e-2, 1e-6}) {
      CAPTURE(dt_ms);
      CAPTURE(tolerance_mV);
      const auto reference = direct_solve(dense_laplacian(tissue, 1000.0, 0.3), C, V, dt_ms);
      // The solve has work to do: the start (V itself) is far from the answer.
      REQUIRE(max_difference(V, reference) > 100 * tolerance_mV);
      std::vector<double> x = V;
      coupler.implicit_step(x.data(), dt_ms, tolerance_mV);
      // CG's guarantee is |x - x*|_inf <= tolerance; the dense solve's own
      // rounding is ~ cond(A) eps |x| < 1e4 x 2e-16 x 85 mV ~ 2e-10 mV, hence
      // the 1e-9 mV allowed beside it.
      CHECK(max_difference(x, reference) <= tolerance_mV + 1e-9);
      // The isolated last cell keeps its potential.
      CHECK(x.back() == doctest::Approx(V.back()).epsilon(1e-12));
    }
  }
  // Ten solves, each of which had to iterate.
  CHECK(coupler.describe_solves().find("10 coupling solves") == 0);
}

TEST_CASE("coupling CG: a solve that cannot converge stops with a clear error") {
  const Tissue tissue = irregular_tissue();
  const auto C = capacitances(tissue);
  GapJunctionCoupler coupler(tissue, kSeedJunctions, C);
  const auto V = potentials(tissue.cell_count());
  SUBCASE("too few iterations for the tolerance") {
    CouplingCg cg(dense_laplacian(tissue, 1000.0, 0.3).sparseView().eval(), C, 2);
    std::vector<double> x = V;
    CHECK_THROWS_WITH_AS(cg.solve(x.data(), 10.0, 1e-6),
                         doctest::Contains("did not reach the tolerance of 1e-06 mV on the potential in 2 iterations"),
                         std::runtime_error);
  }
  SUBCASE("a tolerance below rounding") {
    std::vector<double> x = V;
    CHECK_THROWS_WITH_AS(coupler.implicit_step(x.data(), 1.0, 1e-300),
                         doctest::Contains("did not reach the tolerance of 1e-300 mV"), std::runtime_error);
  }
}

TEST_CASE("gap-junction coupling: currents -L V and total conductances from the CG's slices of L") {
  const Tissue tissue = irregular_tissue();
  const auto C = capacitances(tissue);
  GapJunctionCoupler coupler(tissue, kSeedJunctions, C);
  const auto V = potentials(tissue.cell_count());
  const Eigen::MatrixXd L = dense_laplacian(tissue, 1000.0, 0.3);
  const Eigen::VectorXd reference = -L * Eigen::Map<const Eigen::VectorXd>(V.data(), static_cast<Eigen::Index>(V.size()));
  std::vector<double> added(V.size(), 0.0);
  coupler.add_current(V.data(), added.data());
  std::vector<int> cells(V.size());
  for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<int>(cells.size() - 1 - i);  // any order
  std::vector<double> into(V.size());
  coupler.current_into(V.data(), cells.data(), cells.size(), into.data());
  const std::vector<double> total = coupler.total_conductance_nS();
  for (std::size_t i = 0; i < V.size(); ++i) {
    CAPTURE(i);
    const auto row = static_cast<Eigen::Index>(i);
    // Terms up to ~1e5 pA (1000 nS x 100 mV): the two sums round apart by a
    // few eps of that, ~1e-10 pA.
    CHECK(std::abs(added[i] - reference(row)) <= 1e-9);
    CHECK(into[cells.size() - 1 - i] == added[i]);  // the same sum, cell by cell or all at once
    CHECK(total[i] == doctest::Approx(L(row, row)).epsilon(1e-14));
  }
  CHECK(total.back() == 0.0);  // the isolated cell
}

TEST_CASE("junction Laplacian: written row by row, the matrix a sum of triplets gives, own rows alone too") {
  // Conductances that differ junction by junction (so that the diagonals sum
  // inexactly, and their order shows): a coupling map along y, each cell at
  // y = its number, and fibroblast junctions at D_f 0 (left out: a row can
  // have no entry).
  Tissue tissue = irregular_tissue();
  const auto n = static_cast<Eigen::Index>(tissue.cell_count());
  tissue.x_um.assign(tissue.cell_count(), 0.0);
  for (Eigen::Index c = 0; c < n; ++c) tissue.y_um.push_back(static_cast<double>(c));
  CouplingField field;
  field.x_min_um = -1, field.x_max_um = 1, field.y_min_um = 0, field.y_max_um = static_cast<double>(n);
  field.rows = static_cast<int>(n) + 1, field.columns = 2;
  field.between = CouplingField::Between::nearest;
  for (int row = 0; row < field.rows; ++row)
    for (int column = 0; column < 2; ++column) field.scale.push_back(1.0 + 0.0137 * (row % 7) + 0.001 * column);
  const JunctionConductances junctions{1000.0, 1000.0, 0.0};
  // The reference: every junction's four entries as triplets, duplicates
  // (the diagonals) summed in the order given by Eigen's setFromTriplets;
  // with own rows, only theirs.
  const auto summed_triplets = [&](const std::vector<char>* own_rows) {
    std::vector<Eigen::Triplet<double>> entries;
    for (const auto& [i, j] : tissue.cell_edges) {
      const bool myocytes = tissue.type[i] == CellType::myocyte && tissue.type[j] == CellType::myocyte;
      const double g = myocytes ? 1000.0 * field.scale_at(0.0, 0.5 * (i + j)) : 0.0;
      if (g == 0.0) continue;
      if (!own_rows || (*own_rows)[i]) entries.emplace_back(i, i, g), entries.emplace_back(i, j, -g);
      if (!own_rows || (*own_rows)[j]) entries.emplace_back(j, j, g), entries.emplace_back(j, i, -g);
    }
    CouplingCg::Laplacian L(n, n);
    L.setFromTriplets(entries.begin(), entries.end());
    L.makeCompressed();
    return L;
  };
  const auto check_same = [](const CouplingCg::Laplacian& a, const CouplingCg::Laplacian& b) {
    REQUIRE(a.nonZeros() == b.nonZeros());
    for (Eigen::Index r = 0; r <= a.rows(); ++r) CHECK(a.outerIndexPtr()[r] == b.outerIndexPtr()[r]);
    for (Eigen::Index e = 0; e < a.nonZeros(); ++e) {
      CAPTURE(e);
      CHECK(a.innerIndexPtr()[e] == b.innerIndexPtr()[e]);
      CHECK(a.valuePtr()[e] == b.valuePtr()[e]);  // the same bits
    }
  };
  SUBCASE("every row") { check_same(junction_laplacian_nS(tissue, junctions, {}, &field), summed_triplets(nullptr)); }
  SUBCASE("a rank's rows, in its held numbers") {
    // Every third cell the rank's; its ghosts the other cells joined to one.
    std::vector<char> own(tissue.cell_count(), 0);
    for (std::size_t c = 0; c < own.size(); c += 3) own[c] = 1;
    RankCells share;
    for (std::size_t c = 0; c < own.size(); ++c)
      if (own[c]) share.owned.push_back(static_cast<int>(c));
    for (const auto& [i, j] : tissue.cell_edges) {
      if (own[i] && !own[j]) share.ghosts.push_back(j);
      if (own[j] && !own[i]) share.ghosts.push_back(i);
    }
    std::sort(share.ghosts.begin(), share.ghosts.end());
    share.ghosts.erase(std::unique(share.ghosts.begin(), share.ghosts.end()), share.ghosts.end());
    const CellNumbering held(tissue.cell_count(), share);
    const CouplingCg::Laplacian L = junction_laplacian_nS(tissue, junctions, {}, &field, &held);
    const CouplingCg::Laplacian reference = summed_triplets(&own);
    REQUIRE(L.rows() == static_cast<Eigen::Index>(held.held()));
    // Each own row: the reference row's entries, its columns by held number,
    // in the reference's (tissue) order, with the same bits; no other row.
    for (std::size_t k = 0; k < held.held(); ++k) {
      CAPTURE(k);
      const auto row = static_cast<Eigen::Index>(k);
      const int* outer = L.outerIndexPtr();
      if (k >= held.own()) {
        CHECK(outer[row + 1] == outer[row]);
        continue;
      }
      const int cell = held.tissue_cell(k);
      const int* ref_outer = reference.outerIndexPtr();
      REQUIRE(outer[row + 1] - outer[row] == ref_outer[cell + 1] - ref_outer[cell]);
      for (int e = 0; e < outer[row + 1] - outer[row]; ++e) {
        CHECK(held.tissue_cell(static_cast<std::size_t>(L.innerIndexPtr()[outer[row] + e])) ==
              reference.innerIndexPtr()[ref_outer[cell] + e]);
        CHECK(L.valuePtr()[outer[row] + e] == reference.valuePtr()[ref_outer[cell] + e]);
      }
    }
  }
}

TEST_CASE("coupling CG: a potential that is not finite is left for the caller to see") {
  const Tissue tissue = irregular_tissue();
  const auto C = capacitances(tissue);
  GapJunctionCoupler coupler(tissue, kSeedJunctions, C);
  auto x = potentials(tissue.cell_count());
  x[5] = std::numeric_limits<double>::quiet_NaN();
  CHECK_NOTHROW(coupler.implicit_step(x.data(), 0.1, 1e-3));
  CHECK(std::any_of(x.begin(), x.end(), [](double v) { return std::isnan(v); }));
}

TEST_CASE("coupling CG: the same bits on one thread and on two" * doctest::test_suite("threads")) {
  // 200 x 200 cells (a 4-neighbour lattice of myocytes with a fibroblast
  // column): above kParallelCells, so the passes run on the threads.
  Tissue tissue;
  const int side = 200;
  for (int i = 0; i < side * side; ++i)
    tissue.type.push_back(i % side == 57 ? CellType::fibroblast : CellType::myocyte);
  for (int row = 0; row < side; ++row)
    for (int col = 0; col < side; ++col) {
      const int i = row * side + col;
      if (col + 1 < side) tissue.cell_edges.emplace_back(i, i + 1);
      if (row + 1 < side) tissue.cell_edges.emplace_back(i, i + side);
    }
  const auto C = capacitances(tissue);
  const auto V = potentials(tissue.cell_count());
  const int threads_before = omp_get_max_threads();
  std::vector<std::vector<double>> results;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    GapJunctionCoupler coupler(tissue, kSeedJunctions, C);
    std::vector<double> x = V;
    coupler.implicit_step(x.data(), 0.5, 1e-6);
    results.push_back(x);
  }
  omp_set_num_threads(threads_before);
  CHECK(max_difference(results[0], V) > 1.0);  // it moved
  CHECK(results[0] == results[1]);              // bit for bit
}

TEST_CASE("coupling CG: after restart_implicit a solve gives the bits of a fresh coupler's") {
  // A solve starts from the last solve's correction; a resumed run restarts
  // its integrator and so the coupler, and must give the same numbers as a
  // run never stopped, which restarts it at the same time.
  const Tissue tissue = irregular_tissue();
  const auto C = capacitances(tissue);
  const auto V = potentials(tissue.cell_count());
  GapJunctionCoupler used(tissue, kSeedJunctions, C), fresh(tissue, kSeedJunctions, C);
  std::vector<double> before = V;
  used.implicit_step(before.data(), 0.2, 1e-4);
  std::reverse(before.begin(), before.end());  // another potential for the next solve
  std::vector<double> a = before, b = before;
  used.restart_implicit();
  used.implicit_step(a.data(), 0.1, 1e-4);
  fresh.implicit_step(b.data(), 0.1, 1e-4);
  CHECK(a == b);
}
