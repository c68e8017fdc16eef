// How a run split over ranks ends when it does not complete: a rank that
// fails (a blow-up on its own cells) leaves summary.json "failed" with its
// error, whichever rank it is; SIGTERM to mpirun stops every rank at the
// same step with the outputs one process writes when interrupted.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "run/simulation.hpp"
#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"
#include "tissue/cell_partition.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");

namespace {

json summary_of(const fs::path& dir) { return json::parse(testing::read_file(dir / "summary.json")); }

// A myocyte of the shared sheet that the split over `ranks` gives to `rank`,
// with no neighbour on another rank (its blow-up stays on its rank's cells
// for the step that finds it).
std::size_t inner_myocyte_of(const json& manifest, int ranks, int rank) {
  const Simulation built(parse_scene(manifest));
  const Tissue& tissue = built.tissue();
  const CellPartition partition = partition_cells(tissue, ranks);
  std::vector<char> at_border(tissue.cell_count(), 0);
  for (const auto& [a, b] : tissue.cell_edges)
    if (partition.part_of[a] != partition.part_of[b]) at_border[a] = at_border[b] = 1;
  for (std::size_t cell = 0; cell < tissue.cell_count(); ++cell)
    if (partition.part_of[cell] == rank && !at_border[cell] && tissue.type[cell] == CellType::myocyte) return cell;
  FAIL("no inner myocyte on rank " << rank);
  return 0;
}

}  // namespace

TEST_CASE("mpirun -n 2: a rank other than 0 that fails leaves summary.json failed with its error") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_failures");
  json m = testing::split_sheet_planar_wave(20);
  // 10 uA into one of rank 1's myocytes for 1 ms: V leaves [-250, 250] mV
  // within the step (rush_larsen at 0.01 ms), on rank 1 only.
  const std::size_t cell = inner_myocyte_of(m, 2, 1);
  m["stimulus"].push_back({{"target", json::array({cell})}, {"start_ms", 5}, {"duration_ms", 1}, {"amplitude_pA", 1e7}});
  std::ofstream(dir / "scene.json") << m.dump();

  CHECK(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "out") != 0);
  const json summary = summary_of(dir / "out");
  INFO(summary.dump(1));
  CHECK(summary["status"] == "failed");
  const std::string error = summary["error"];
  CHECK(error.find("rank 1 of 2: blow-up at t = 5.01 ms: cell " + std::to_string(cell) + " (myocyte") == 0);
  CHECK(summary["mpi_ranks"] == 2);
  CHECK(summary["manifest"]["name"] == "planar");
  // And the same run in one process fails at the same cell and time.
  CHECK(testing::run_scene("", dir / "scene.json", dir / "one") != 0);
  const std::string one_error = summary_of(dir / "one")["error"];
  CHECK(one_error.find("blow-up at t = 5.01 ms: cell " + std::to_string(cell) + " (myocyte") == 0);
}

TEST_CASE("mpirun -n 2: SIGTERM to mpirun stops every rank at one step, with the outputs written") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_interrupted");
  json m = testing::split_sheet_planar_wave(1e7);  // far longer than the test waits
  std::ofstream(dir / "scene.json") << m.dump();
  const fs::path out = dir / "out";
  // Signalled once the run has started (its first summary.json written).
  const std::string summary_file = (out / "summary.json").string();
  // (mpirun passes SIGTERM on after odls_base_sigkill_timeout seconds and
  // kills its ranks as many later, docs/guide/parallel.md: 1 s by default,
  // which a loaded machine can overrun while the ranks write; 30 s made
  // the case take 58 s. This scene's outputs take ~10 ms to write.)
  const std::string command = testing::mpirun(2) + "--mca odls_base_sigkill_timeout 5 " +
                              std::string(FIBRODEM_BINARY_DIR) + "/fibrodem run --quiet --no-report " +
                              (dir / "scene.json").string() + " --out " + out.string() + " > " +
                              (dir / "out.txt").string() + " 2>&1 & pid=$!; i=0; while [ ! -s " + summary_file +
                              " ] && [ $i -lt 2400 ]; do sleep 0.05; i=$((i + 1)); done; sleep 0.5; kill -TERM $pid; wait $pid";
  const int status = std::system(command.c_str());
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) != 0);
  const json summary = summary_of(out);
  INFO(testing::read_file(dir / "out.txt"));
  CHECK(summary["status"] == "interrupted");
  const double t_ms = summary["simulated_ms"];
  CHECK(t_ms > 0);
  CHECK(summary["error"].get<std::string>().find("interrupted by SIGTERM at t = ") == 0);
  CHECK(testing::read_file(out / "run.log").find("run interrupted") != std::string::npos);
  // traces.csv, gathered from both ranks, whole up to the step both stopped at.
  const std::string traces = testing::read_file(out / "traces.csv");
  CHECK(traces.find("t_ms,V_0,V_150,V_300\n") == 0);
  const std::size_t rows = static_cast<std::size_t>(std::count(traces.begin(), traces.end(), '\n')) - 1;
  CHECK(rows == static_cast<std::size_t>(std::floor(t_ms)) + 1);  // a row a ms from 0
}

TEST_SUITE_END();
