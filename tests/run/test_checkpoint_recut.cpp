// A checkpoint's parts put together cell by cell for another split
// (run/checkpoint_recut.hpp): the parts taken one at a time, values land
// where their cells are, whatever part held them and in whatever order the
// parts come; a part that does not add up, a cell in two parts or in none
// is named. (tests/run/test_mpi_checkpoints.cpp resumes whole runs on
// another number of ranks.)
#include <doctest/doctest.h>

#include <filesystem>
#include <stdexcept>
#include <utility>

#include "run/checkpoint_dir.hpp"
#include "run/checkpoint_recut.hpp"
#include "support/scenes.hpp"

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

// The fields `pick` puts together from the parts, taken in the order given.
CheckpointFields picked(CellPick pick, const std::vector<CheckpointFields>& parts, const std::vector<int>& order,
                        const std::vector<std::string>& rows, const std::vector<std::string>& bytes) {
  for (const int r : order) pick.take(parts[r], r, parts[r].ints("ionic.myocyte.cells"), rows, bytes);
  CheckpointFields out;
  pick.put_into(out);
  return out;
}

TEST_CASE("checkpoint re-cut: each cell's values come from the part that held it, one part at a time") {
  const auto parts = two_parts();
  CHECK(own_cells_of_part(parts[0]) == std::vector<int>{0, 3});
  CHECK(own_cells_of_part(parts[1]) == std::vector<int>{1, 2, 4});
  for (const std::vector<int>& order : {std::vector<int>{0, 1}, std::vector<int>{1, 0}}) {
    const CheckpointFields x = picked(CellPick({4, 0, 2}, 5), parts, order, {"x"}, {});
    CHECK(x.numbers("x") == std::vector<double>{4, 0, 2, 104, 100, 102});
    CHECK(!x.has("b"));
    CHECK(picked(CellPick({2, 3}, 5), parts, order, {}, {"b"}).text("b") == "cCdD");
  }
  CHECK(picked(CellPick({}, 5), parts, {0, 1}, {"x"}, {}).numbers("x").empty());
  // A population none of the parts taken holds (their lists of it empty):
  // its fields are put all the same, empty, as a rank with none of its cells writes them.
  CellPick none({}, 5);
  none.take(parts[0], 0, {}, {"x"}, {"b"});
  CheckpointFields empty;
  none.put_into(empty);
  CHECK(empty.numbers("x").empty());
  CHECK(empty.text("b").empty());
  CellPick pick({3, 1}, 5);
  pick.take(parts[0], 0, {3, 0}, {"x"});
  pick.take(parts[1], 1, {1, 4, 2}, {"x"});
  CHECK(pick.release_rows("x") == std::vector<double>{3, 1, 103, 101});
}

TEST_CASE("checkpoint re-cut: a part that does not add up, a cell twice or in no part is named") {
  auto parts = two_parts();
  CellPick twice({0}, 5);
  twice.take(parts[0], 0, {3, 0}, {"x"});
  CHECK_THROWS_WITH_AS(twice.take(parts[1], 1, {1, 0, 2}, {"x"}), "its parts list cell 0 twice", CheckpointError);
  CHECK_THROWS_WITH_AS(CellPick({0}, 5).take(parts[0], 0, {3, 7}, {"x"}),
                       "its parts list cell 7, which this tissue lacks", CheckpointError);
  CHECK_THROWS_AS(CellPick({5}, 5), std::invalid_argument);  // (a pick of the tissue's cells)
  CellPick uneven({0}, 5);
  uneven.take(parts[0], 0, {3, 0}, {"x"});
  parts[1].put("x", std::vector<double>{1, 2, 3, 4});  // 4 values for 3 cells
  CHECK_THROWS_WITH_AS(uneven.take(parts[1], 1, {1, 4, 2}, {"x"}), "its field 'x' has 4 values for 3 cells in part 1",
                       CheckpointError);
  CellPick more_rows({0}, 5);
  more_rows.take(parts[0], 0, {3, 0}, {"x"});
  parts[1].put("x", std::vector<double>(9, 1.0));  // 3 rows where part 0 has 2
  CHECK_THROWS_WITH_AS(more_rows.take(parts[1], 1, {1, 4, 2}, {"x"}), "its field 'x' has 9 values for 3 cells in part 1",
                       CheckpointError);
  CellPick partial({1}, 5);
  partial.take(parts[0], 0, {3, 0}, {}, {"b"});
  CheckpointFields out;
  CHECK_THROWS_WITH_AS(partial.put_into(out), "no part of it holds cell 1 in 'b'", CheckpointError);
  CHECK_THROWS_WITH_AS(partial.release_rows("x"), "no part of it holds cell 1 in 'x'", CheckpointError);
}

TEST_CASE("checkpoint re-cut: the likely parts are read first, the others only while a cell is missing") {
  // Three parts of a 6-cell tissue on disk: part r holds cells 2r and 2r + 1,
  // field "x" one value a cell (10 * cell).
  const auto dir = testing::scratch_dir("checkpoint_recut_parts");
  const std::filesystem::path file = dir / "t_000000005000us.ckpt";
  std::vector<CheckpointFields> parts(3);
  for (int r = 0; r < 3; ++r) {
    parts[r].put("ionic.myocyte.cells", std::vector<int>{2 * r, 2 * r + 1});
    parts[r].put("x", std::vector<double>{20.0 * r, 20.0 * r + 10});
    parts[r].put_integer("run.mpi_ranks", 3);
    parts[r].put_integer("run.mpi_rank", r);
    parts[r].put("run.time_ms", 5.0);
    if (r > 0) write_checkpoint_file(rank_checkpoint_path(file, r), parts[r]);
  }
  // Rank 0's part is the checkpoint itself, held, not read again.
  const auto take = [&](const std::vector<int>& cells, const std::vector<int>& likely) {
    CellPick pick(cells, 6);
    std::vector<int> visited;
    const int read = take_checkpoint_parts(
        file, parts[0], likely, [&pick] { return pick.complete(); },
        [&](const CheckpointFields& part, int r) {
          visited.push_back(r);
          pick.take(part, r, part.ints("ionic.myocyte.cells"), {"x"});
        });
    CHECK(read == static_cast<int>(visited.size()));
    return std::pair{visited, pick.release_rows("x")};
  };
  CHECK(take({5, 4}, {2}) == std::pair{std::vector<int>{0, 2}, std::vector<double>{50, 40}});
  CHECK(take({1}, {}) == std::pair{std::vector<int>{0}, std::vector<double>{10}});
  // A wrong guess costs reads, not cells: part 1 holds none of them.
  CHECK(take({5, 4}, {1}) == std::pair{std::vector<int>{0, 1, 2}, std::vector<double>{50, 40}});
  CHECK(take({2, 5}, {2}) == std::pair{std::vector<int>{0, 2, 1}, std::vector<double>{20, 50}});
  // A part missing from disk is named.
  std::filesystem::remove(rank_checkpoint_path(file, 2));
  CHECK_THROWS_WITH_AS(take({5}, {2}), doctest::Contains("rank 2's part cannot be read"), CheckpointError);
}
