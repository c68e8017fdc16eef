// The layout of a partition's parts, as rank 0 gathers one value a cell:
// rank after rank, each rank's cells in increasing tissue order.
#include <doctest/doctest.h>

#include <random>

#include "run/rank_layout.hpp"

using namespace fibrodem;

TEST_CASE("a partition's rank layout lists each part's cells, in order, where its offset says") {
  // 1,000 cells dealt at random to 7 parts, one part left empty: each
  // rank's cells are the partition's own list of that part (CellPartition::cells_of).
  CellPartition partition;
  partition.parts = 7;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> part(0, 5);
  for (int cell = 0; cell < 1000; ++cell) partition.part_of.push_back(part(rng));
  const RankLayout layout = rank_layout(partition);
  CHECK(layout.cell_count() == 1000);
  REQUIRE(layout.counts.size() == 7);
  CHECK(layout.counts[6] == 0);
  for (int r = 0; r < 7; ++r) {
    CAPTURE(r);
    const auto cells = layout.cells_of(r);
    CHECK(std::vector<int>(cells.begin(), cells.end()) == partition.cells_of(r));
    if (r > 0) CHECK(layout.offsets[r] == layout.offsets[r - 1] + layout.counts[r - 1]);
  }
}
