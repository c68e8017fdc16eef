// A checkpoint's parts put together cell by cell for another split
// (run/checkpoint_recut.hpp): values land where their cells are, whatever
// part held them; a part that does not add up, a cell in two parts or in
// none is named. (tests/run/test_mpi_checkpoints.cpp resumes whole runs on
// another number of ranks.)
#include <doctest/doctest.h>

#include <stdexcept>

#include "run/checkpoint_recut.hpp"

using namespace fibrodem;

namespace {

// Two parts of a 5-cell tissue: part 0 holds cells 3 and 0, part 1 cells 1,
// 4 and 2. Field "x" has two rows, value 100 * row + cell; field "b" two
// bytes a cell, 'a' + cell and 'A' + cell.
std::vector<CheckpointFields> two_parts() {
  std::vector<CheckpointFields> parts(2);
  const std::vector<std::vector<int>> cells = {{3, 0}, {1, 4, 2}};
  for (std::size_t r = 0; r < 2; ++r) {
    std::vector<double> x;
    std::string b;
    for (int row = 0; row < 2; ++row)
      for (const int cell : cells[r]) x.push_back(100.0 * row + cell);
    for (const int cell : cells[r]) b += {static_cast<char>('a' + cell), static_cast<char>('A' + cell)};
    parts[r].put("x", x);
    parts[r].put_text("b", b);
    parts[r].put("ionic.myocyte.cells", cells[r]);
  }
  return parts;
}

}  // namespace

TEST_CASE("checkpoint re-cut: each cell's values come from the part that held it") {
  const auto parts = two_parts();
  const auto own = own_cells_of_parts(parts);
  REQUIRE(own == std::vector<std::vector<int>>{{0, 3}, {1, 2, 4}});
  const CellPlaces places({{3, 0}, {1, 4, 2}}, 5);
  CHECK(places.rows(parts, "x", {4, 0, 2}) == std::vector<double>{4, 0, 2, 104, 100, 102});
  CHECK(places.bytes(parts, "b", {2, 3}) == "cCdD");
  CHECK(places.rows(parts, "x", {}).empty());
}

TEST_CASE("checkpoint re-cut: a part that does not add up, a cell twice or in no part is named") {
  auto parts = two_parts();
  CHECK_THROWS_WITH_AS(CellPlaces({{3, 0}, {1, 0}}, 5), "its parts list cell 0 twice", CheckpointError);
  CHECK_THROWS_WITH_AS(CellPlaces({{3, 7}}, 5), "its parts list cell 7, which this tissue lacks", CheckpointError);
  const CellPlaces places({{3, 0}, {1, 4, 2}}, 5);
  parts[1].put("x", std::vector<double>{1, 2, 3, 4});  // 4 values for 3 cells
  CHECK_THROWS_WITH_AS(places.rows(parts, "x", {0}), "its field 'x' has 4 values for 3 cells in part 1", CheckpointError);
  const CellPlaces partial({{3, 0}}, 5);
  CHECK_THROWS_WITH_AS(partial.bytes({parts[0]}, "b", {1}), "no part of it holds cell 1 in 'b'", CheckpointError);
  CHECK_THROWS_AS(partial.bytes(parts, "b", {0}), std::invalid_argument);  // a part for each list
}
