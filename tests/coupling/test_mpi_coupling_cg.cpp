// The implicit coupling step split over ranks (run/coupling_over_ranks.hpp,
// coupling/coupling_cg.hpp): each rank's CG solves its own rows, reading its
// ghosts' entries from their owners before each product and reducing its
// sums over the ranks. Run here on ranks that are threads of one process
// (a RankGroup over shared memory), against a dense direct solve of the
// whole system; tests/tissue/test_mpi_tissue.cpp runs it under mpirun.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include "coupling/gap_junction.hpp"
#include "support/coupling_reference.hpp"
#include "support/thread_ranks.hpp"
#include "run/coupling_over_ranks.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/cell_partition.hpp"
#include "tissue/rank_cells.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");
using test::max_difference;
using test::ThreadRanks;

namespace {

// A 9 x 12 sheet, 4-neighbour junctions, every fifth cell a fibroblast.
Tissue sheet() {
  Tissue tissue;
  const int width = 9, height = 12;
  for (int i = 0; i < width * height; ++i) tissue.type.push_back(i % 5 == 2 ? CellType::fibroblast : CellType::myocyte);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int i = y * width + x;
      if (x + 1 < width) tissue.cell_edges.push_back({i, i + 1});
      if (y + 1 < height) tissue.cell_edges.push_back({i, i + width});
    }
  return tissue;
}

constexpr double kD_m_nS = 1000, kD_f_nS = 0.3;  // the seed paper's

std::vector<double> capacitances(const Tissue& tissue) {
  std::vector<double> C;
  for (CellType type : tissue.type) C.push_back(type == CellType::myocyte ? 100.0 : 6.3);
  return C;
}

// Per-cell values by tissue cell, in `held`'s numbers.
std::vector<double> held_values(const std::vector<double>& by_cell, const CellNumbering& held) {
  std::vector<double> values(held.held());
  for (std::size_t c = 0; c < values.size(); ++c) values[c] = by_cell[static_cast<std::size_t>(held.tissue_cell(c))];
  return values;
}

// A wavefront: the upper third depolarised.
std::vector<double> potentials(std::size_t n) {
  std::vector<double> V;
  for (std::size_t i = 0; i < n; ++i) V.push_back(i < n / 3 ? 20.0 : -80.0 + 0.1 * static_cast<double>(i % 7));
  return V;
}

// The reference: (C/dt + L)^-1 (C/dt) V, dense.
std::vector<double> direct_solve(const Tissue& tissue, const std::vector<double>& C, const std::vector<double>& V,
                                 double dt_ms) {
  return test::direct_solve(test::dense_laplacian(tissue, kD_m_nS, kD_f_nS), C, V, dt_ms);
}

// each(group, share) on `ranks` threads at once, each a rank of the tissue's
// partition (its results the caller's to guard).
template <class Each>
void on_thread_ranks(const Tissue& tissue, int ranks, bool drop_halo, Each&& each) {
  // (The sheet is a graph without centres: Scotch cuts it.)
  const CellPartition partition = partition_cells(tissue, ranks, PartitionMethod::scotch);
  ThreadRanks all(ranks, drop_halo);
  all.run([&](ThreadRanks::Group& group) { each(group, rank_cells(tissue, partition, group.rank())); });
  CHECK(all.layouts_agree);
}

struct SplitSolve {
  std::vector<double> V;                       // every rank's own cells' solution, by global cell
  std::vector<std::string> statistics;         // each rank's describe_solves()
  std::vector<long long> exchanges;            // each rank's CG halo exchanges
};

// Two implicit steps (dt_ms, then dt_ms / 2 from its result: the second
// starts from the first's correction) on `ranks` threads, each a rank.
SplitSolve solve_split(int ranks, bool drop_halo, double dt_ms, double tolerance_mV) {
  const Tissue tissue = sheet();
  const auto C = capacitances(tissue);
  SplitSolve result{std::vector<double>(tissue.cell_count(), std::nan("")), std::vector<std::string>(ranks),
                    std::vector<long long>(ranks)};
  std::mutex result_mutex;
  on_thread_ranks(tissue, ranks, drop_halo, [&](ThreadRanks::Group& group, const RankCells& share) {
    const int r = share.rank;
    // The rank's own cells, then its ghosts (held numbers); the ghosts hold
    // a stale value (as in a run): the solve must not read them.
    const CellNumbering held(tissue.cell_count(), share);
    CouplingOverRanks coupler(tissue, JunctionConductances{kD_m_nS, kD_m_nS, kD_f_nS}, held_values(C, held), {},
                              nullptr, group, share, held);
    const std::vector<double> V_tissue = potentials(tissue.cell_count());
    std::vector<double> V(held.held(), 1e3);
    for (std::size_t c = 0; c < held.own(); ++c) V[c] = V_tissue[static_cast<std::size_t>(held.tissue_cell(c))];
    coupler.implicit_step(V.data(), dt_ms, tolerance_mV);
    coupler.implicit_step(V.data(), 0.5 * dt_ms, tolerance_mV);
    std::lock_guard<std::mutex> lock(result_mutex);
    for (std::size_t c = 0; c < held.own(); ++c) result.V[static_cast<std::size_t>(held.tissue_cell(c))] = V[c];
    result.statistics[static_cast<std::size_t>(r)] = coupler.describe_solves();
    result.exchanges[static_cast<std::size_t>(r)] = coupler.exchanges();
  });
  return result;
}

}  // namespace

TEST_CASE("coupling CG over 2 and 3 ranks: within its tolerance of a direct solve, every rank alike") {
  const Tissue tissue = sheet();
  const auto C = capacitances(tissue);
  for (const double dt_ms : {0.01, 0.5}) {
    const double tolerance_mV = 1e-6;
    CAPTURE(dt_ms);
    const auto V0 = potentials(tissue.cell_count());
    const auto reference = direct_solve(tissue, C, direct_solve(tissue, C, V0, dt_ms), 0.5 * dt_ms);
    // The solve has work to do: the start is far from the answer.
    REQUIRE(max_difference(V0, reference) > 1e4 * tolerance_mV);
    for (const int ranks : {2, 3}) {
      CAPTURE(ranks);
      const SplitSolve split = solve_split(ranks, false, dt_ms, tolerance_mV);
      // Each solve within the tolerance of its exact answer (CG's bound,
      // coupling_cg.hpp); the second's start carries the first's error
      // (at most the tolerance, which (I + K)^-1, of max norm 1, does not
      // grow); the dense solve's own rounding ~1e-10 mV.
      CHECK(max_difference(split.V, reference) <= 2 * tolerance_mV + 1e-9);
      // Every rank took the same iterations (its decisions come from sums
      // reduced over the ranks), and each exchanged ghosts as it iterated.
      for (int r = 1; r < ranks; ++r) CHECK(split.statistics[static_cast<std::size_t>(r)] == split.statistics[0]);
      CHECK(split.statistics[0].find("2 coupling solves") == 0);
      for (long long exchanges : split.exchanges) CHECK(exchanges >= 4);
      // The same number of ranks: the same bits.
      CHECK(solve_split(ranks, false, dt_ms, tolerance_mV).V == split.V);
    }
  }
}

TEST_CASE("coupling over 2 and 3 ranks: each rank's rows give one process's currents, bit for bit") {
  // A rank holds its own rows of L only, their columns numbered its own way;
  // each row must still sum the terms of the whole tissue's row in its order.
  const Tissue tissue = sheet();
  const auto C = capacitances(tissue);
  const JunctionConductances g_nS{kD_m_nS, kD_m_nS, kD_f_nS};
  const GapJunctionCoupler whole(tissue, g_nS, C);
  std::vector<double> V = potentials(tissue.cell_count());
  for (std::size_t i = 0; i < V.size(); ++i) V[i] += 1e-3 * std::sin(static_cast<double>(i));  // no two alike
  std::vector<double> every(tissue.cell_count());
  for (int i = 0; i < static_cast<int>(every.size()); ++i) whole.current_into(V.data(), &i, 1, &every[static_cast<std::size_t>(i)]);
  for (const int ranks : {2, 3}) {
    CAPTURE(ranks);
    std::vector<double> split(tissue.cell_count(), std::nan("")), added(tissue.cell_count(), 0.0);
    std::vector<double> rates(static_cast<std::size_t>(ranks));
    std::mutex result_mutex;
    on_thread_ranks(tissue, ranks, false, [&](ThreadRanks::Group& group, const RankCells& share) {
      // Held numbers: the rank's own cells (0, 1, ...), then its ghosts,
      // their potentials as a halo exchange leaves them.
      const CellNumbering held(tissue.cell_count(), share);
      const CouplingOverRanks coupler(tissue, g_nS, held_values(C, held), {}, nullptr, group, share, held);
      const std::vector<double> V_held = held_values(V, held);
      std::vector<double> mine(held.own()), own_added(held.held(), 0.0);
      std::vector<int> own(held.own());
      for (std::size_t c = 0; c < held.own(); ++c) own[c] = static_cast<int>(c);
      coupler.current_into(V_held.data(), own.data(), own.size(), mine.data());
      coupler.add_current(V_held.data(), own_added.data());
      std::lock_guard<std::mutex> lock(result_mutex);
      for (std::size_t c = 0; c < held.own(); ++c) {
        const auto cell = static_cast<std::size_t>(held.tissue_cell(c));
        split[cell] = mine[c];
        added[cell] = own_added[c];
      }
      // Nothing goes into a ghost.
      CHECK(std::all_of(own_added.begin() + static_cast<long>(held.own()), own_added.end(),
                        [](double i) { return i == 0.0; }));
      rates[static_cast<std::size_t>(share.rank)] = coupler.max_rate_per_ms();
    });
    CHECK(split == every);
    CHECK(added == every);
    // The stability limit's rate is the whole tissue's on every rank.
    for (double rate : rates) CHECK(rate == whole.max_rate_per_ms());
  }
}

TEST_CASE("coupling CG over 2 ranks: without the ghosts' exchange the solve is wrong") {
  // The check above can fail: with the exchange dropped, each rank's ghosts
  // hold zeros (never their owners' potentials) and the split solve is far
  // from the answer on the cells along the ranks' border.
  const Tissue tissue = sheet();
  const auto C = capacitances(tissue);
  const double dt_ms = 0.5, tolerance_mV = 1e-6;
  const auto V0 = potentials(tissue.cell_count());
  const auto reference = direct_solve(tissue, C, direct_solve(tissue, C, V0, dt_ms), 0.5 * dt_ms);
  CHECK(max_difference(solve_split(2, true, dt_ms, tolerance_mV).V, reference) > 1e3 * tolerance_mV);
}

TEST_SUITE_END();
