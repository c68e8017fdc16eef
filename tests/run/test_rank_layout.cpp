// The layout of a partition's parts, as rank 0 gathers one value a cell:
// rank after rank, each rank's cells in increasing tissue order.
#include <doctest/doctest.h>

#include <random>

#include "run/rank_layout.hpp"

using namespace fibrodem;

TEST_CASE("a partition's rank layout lists each part's cells, in order, where its offset says") {
  // 1,000 cells dealt at random to 7 parts, one part left empty: each
  // rank's cells are those the partition puts in its part, in order; the
  // counts and offsets alone (rank_layout_counts) are the same.
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
    std::vector<int> expected;
    for (int cell = 0; cell < 1000; ++cell)
      if (partition.part_of[static_cast<std::size_t>(cell)] == r) expected.push_back(cell);
    CHECK(std::vector<int>(cells.begin(), cells.end()) == expected);
    if (r > 0) CHECK(layout.offsets[r] == layout.offsets[r - 1] + layout.counts[r - 1]);
  }
  const RankLayout counts_only = rank_layout_counts(partition.sizes());
  CHECK(counts_only.counts == layout.counts);
  CHECK(counts_only.offsets == layout.offsets);
  CHECK(counts_only.cells_in_rank_order.empty());
}
