// Checkpoints of a run split over MPI ranks and `mpirun -n N fibrodem
// resume` (docs/guide/parallel.md, docs/reference/outputs.md): each rank writes
// its own cells' part, rank 0 the checkpoint with the rank count, last. A
// split run killed (SIGKILL, every rank at the same step, or halfway
// through writing a rank's part) and resumed on as many ranks writes the
// same traces.csv and biomarkers.csv as the run never stopped, and so does
// one resumed on another count (every part read, each rank's cells taken
// out of them: run/checkpoint_recut.hpp) or in one process, and a
// one-process checkpoint resumed split. The reference is the uninterrupted
// run: a fixed-step explicit run split over ranks computes one process's
// potentials bit for bit, whatever the count. A checkpoint named by
// initial_state.from, one process's or a split run's, starts a split run as
// it starts one process's (each rank takes its own cells' states).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");
namespace fs = std::filesystem;

namespace {

json summary_of(const fs::path& dir) { return json::parse(testing::read_file(dir / "summary.json")); }

// `fibrodem run` of the scene under the launcher, killed as FIBRODEM_TEST_KILL
// says (empty: not killed).
int run(const std::string& launcher, const fs::path& scene, const fs::path& out, const std::string& kill = "") {
  return testing::run_scene((kill.empty() ? "" : "FIBRODEM_TEST_KILL=" + kill + " ") + launcher, scene, out);
}

// `fibrodem resume out` under the launcher; its output in out.resume.txt.
int resume(const std::string& launcher, const fs::path& out) {
  return testing::run_fibrodem(launcher, "resume --quiet --no-report " + out.string(), out.string() + ".resume.txt");
}

void check_same_outputs(const fs::path& reference, const fs::path& resumed) {
  const std::string traces = testing::read_file(reference / "traces.csv");
  REQUIRE(traces.size() > 1000);
  CHECK(testing::read_file(resumed / "traces.csv") == traces);
  CHECK(testing::read_file(resumed / "biomarkers.csv") == testing::read_file(reference / "biomarkers.csv"));
  const json a = summary_of(reference), b = summary_of(resumed);
  CHECK(b["status"] == "completed");
  CHECK(b["steps"] == a["steps"]);
  // output.reentry measured over the whole record: its frames before the
  // checkpoint come back from the log beside it (run/frame_log.hpp).
  CHECK(b.value("reentry", json()).dump() == a.value("reentry", json()).dump());
  if (fs::exists(reference / "phase_singularities.csv"))
    CHECK(testing::read_file(resumed / "phase_singularities.csv") ==
          testing::read_file(reference / "phase_singularities.csv"));
}

}  // namespace

TEST_CASE("mpirun -n 2: a split run killed and resumed on 2 ranks writes the outputs of one never stopped") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_checkpoints");
  // The wave crosses the sheet within its first 4 ms; 30 ms of rush_larsen
  // at 0.01 ms is 3000 steps, checkpoints at 10 and 20 ms (steps 1000 and 2000).
  json m = testing::split_sheet_planar_wave(30);
  m["output"]["traces"][0]["every_ms"] = 0.25;
  m["output"]["checkpoint"] = {{"every_ms", 10}, {"keep", 1}};
  m["output"]["reentry"] = {{"every_ms", 0.25}, {"tau_ms", 1}};
  std::ofstream(dir / "scene.json") << m.dump();
  const std::string two = testing::mpirun(2);

  REQUIRE(run(two, dir / "scene.json", dir / "reference") == 0);
  REQUIRE(summary_of(dir / "reference")["steps"] == 3000);
  // The premise of the re-entry check: the wave's activations fall before
  // the first checkpoint, so a resumed run that measured only from where it
  // resumed would find none.
  REQUIRE(summary_of(dir / "reference")["reentry"]["beats"][0]["last_activation_ms"].get<double>() < 10);

  // Killed at step 2500, after the checkpoint at 20 ms.
  REQUIRE(run(two, dir / "scene.json", dir / "killed", "step:2500") != 0);
  REQUIRE(summary_of(dir / "killed")["status"] == "running");
  const fs::path checkpoints = dir / "killed" / "checkpoints";
  CHECK(fs::exists(checkpoints / "t_000000020000us.ckpt"));
  CHECK(fs::exists(checkpoints / "t_000000020000us.rank1.ckpt"));
  CHECK_FALSE(fs::exists(checkpoints / "t_000000010000us.rank1.ckpt"));  // pruned with its checkpoint (keep 1)
  const std::string killed_summary = testing::read_file(dir / "killed" / "summary.json");

  // Resumed in one process, or on 3 ranks: the parts cut again for them.
  for (const auto& [launcher, name, ranks] :
       {std::tuple{std::string(), "killed_one", 1}, std::tuple{testing::mpirun(3), "killed_three", 3}}) {
    const std::string folder = name;  // (clang 14 cannot capture a structured binding)
    CAPTURE(folder);
    fs::copy(dir / "killed", dir / folder, fs::copy_options::recursive);
    REQUIRE(resume(launcher, dir / folder) == 0);
    check_same_outputs(dir / "reference", dir / folder);
    CHECK(summary_of(dir / folder)["resumed_from"]["time_ms"] == 20);
    CHECK(summary_of(dir / folder)["mpi_ranks"] == ranks);
    CHECK(testing::read_file(dir / folder / "run.log").find("written split over 2 MPI ranks; its parts cut again for this run") !=
          std::string::npos);
  }

  // Without the re-entry frames' log, rank 0 measures re-entry from the
  // resume, and rank 1 follows it (the ranks gather every sample together).
  fs::copy(dir / "killed", dir / "killed_lost", fs::copy_options::recursive);
  REQUIRE(fs::remove(dir / "killed_lost" / "checkpoints" / "reentry_V.frames"));
  REQUIRE(resume(two, dir / "killed_lost") == 0);
  CHECK(summary_of(dir / "killed_lost")["status"] == "completed");
  CHECK(testing::read_file(dir / "killed_lost" / "run.log").find("re-entry is measured from t = 20 ms") !=
        std::string::npos);
  CHECK(testing::read_file(dir / "killed_lost" / "traces.csv") == testing::read_file(dir / "reference" / "traces.csv"));

  REQUIRE(resume(two, dir / "killed") == 0);
  check_same_outputs(dir / "reference", dir / "killed");
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"] == 20);
  CHECK(summary_of(dir / "killed")["mpi_ranks"] == 2);

  // Killed halfway through writing rank 1's part of the second checkpoint:
  // rank 0 had not written the checkpoint, so the resume takes the first.
  REQUIRE(run(two, dir / "scene.json", dir / "killed_writing", "checkpoint:2") != 0);
  CHECK_FALSE(fs::exists(dir / "killed_writing" / "checkpoints" / "t_000000020000us.ckpt"));
  REQUIRE(resume(two, dir / "killed_writing") == 0);
  check_same_outputs(dir / "reference", dir / "killed_writing");
  CHECK(summary_of(dir / "killed_writing")["resumed_from"]["time_ms"] == 10);

}

TEST_CASE("mpirun -n 2: the adaptive method split, killed and resumed on 2 ranks, writes the same outputs") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  // Its step control and coupling CG reduce over the ranks (the same bits
  // for the same count), and it starts afresh at each checkpoint, resumed
  // or not: the same steps.
  const auto dir = testing::scratch_dir("mpi_checkpoints_adaptive");
  json m = testing::split_sheet_planar_wave(30);
  m["solver"] = {{"method", "adaptive"}};
  m["output"]["traces"][0]["every_ms"] = 0.25;
  m["output"]["checkpoint"] = {{"every_ms", 10}};
  std::ofstream(dir / "scene.json") << m.dump();
  const std::string two = testing::mpirun(2);
  REQUIRE(run(two, dir / "scene.json", dir / "reference") == 0);
  const long long steps = summary_of(dir / "reference")["steps"].get<long long>();
  REQUIRE(run(two, dir / "scene.json", dir / "killed", "step:" + std::to_string(steps * 9 / 10)) != 0);
  REQUIRE(resume(two, dir / "killed") == 0);
  check_same_outputs(dir / "reference", dir / "killed");
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"].get<double>() >= 10);
}

TEST_CASE("mpirun -n 2: a one-process checkpoint resumed split writes one process's outputs") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_checkpoints_one");
  json m = testing::split_sheet_planar_wave(20);
  m["output"]["traces"][0]["every_ms"] = 0.25;
  m["output"]["checkpoint"] = {{"every_ms", 10}};
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(run("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(run("", dir / "scene.json", dir / "killed", "step:1500") != 0);
  // traces.csv and biomarkers.csv as one process wrote them up to its kill
  // are replaced by the split run's, written whole at its end.
  REQUIRE(resume(testing::mpirun(2), dir / "killed") == 0);
  check_same_outputs(dir / "one", dir / "killed");
  CHECK(summary_of(dir / "killed")["mpi_ranks"] == 2);
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"] == 10);
}

TEST_CASE("mpirun -n 2 then 3: a fibrotic sheet's checkpoint resumed on ranks that hold part of the graph") {
  // On fibrotic_sheet (cut by rcb, no mechanics) ranks other than 0 never
  // hold the whole cell graph nor every cell's centre: resumed on 3 ranks,
  // ranks 1 and 2 guess which of the 2-rank checkpoint's parts hold their
  // cells by cutting the cells the builder hands over one by one again, with
  // the whole graph's pitch. The outputs are those of one process never
  // stopped.
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_checkpoints_partial_graph");
  json m = testing::split_fibrotic_sheet_planar_wave(20, "fibroblasts");
  m["output"]["traces"][0]["every_ms"] = 0.25;
  m["output"]["checkpoint"] = {{"every_ms", 10}};
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(run("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(run(testing::mpirun(2), dir / "scene.json", dir / "killed", "step:1500") != 0);
  REQUIRE(resume(testing::mpirun(3), dir / "killed") == 0);
  check_same_outputs(dir / "one", dir / "killed");
  CHECK(summary_of(dir / "killed")["mpi_ranks"] == 3);
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"] == 10);
  // (The premise: the scene has fibroblasts, so cells' numbers skip slots'.)
  CHECK(testing::read_file(dir / "one" / "biomarkers.csv").find("fibroblast") != std::string::npos);
}

namespace {

// traces.csv's row at time t_ms, without its time column (empty if none).
std::string trace_row_at(const std::string& csv, double t_ms) {
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line))
    if (std::stod(line.substr(0, line.find(','))) == t_ms) return line.substr(line.find(','));
  return "";
}

}  // namespace

TEST_CASE("mpirun -n 2: initial_state.from a one-process checkpoint gives one process's outputs") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_initial_state");
  // The source's checkpoint at 3 ms catches the stimulated edge (stimulus
  // 2-4 ms) on its way up while the rest of the sheet is at rest: the cells'
  // states differ from cell to cell, so a state given to the wrong cell
  // would show.
  json source = testing::split_sheet_planar_wave(6);
  source["output"]["checkpoint"] = {{"every_ms", 3}};
  std::ofstream(dir / "source.json") << source.dump();
  REQUIRE(run("", dir / "source.json", dir / "source") == 0);
  REQUIRE(run(testing::mpirun(2), dir / "source.json", dir / "source_two") == 0);

  json branch = testing::split_sheet_planar_wave(6);
  branch["output"]["traces"][0]["every_ms"] = 0.25;
  branch["initial_state"] = {{"from", (dir / "source").string()}, {"time_ms", 3}};
  std::ofstream(dir / "branch.json") << branch.dump();
  REQUIRE(run("", dir / "branch.json", dir / "one") == 0);
  REQUIRE(run(testing::mpirun(2), dir / "branch.json", dir / "two") == 0);
  CHECK(summary_of(dir / "two")["mpi_ranks"] == 2);
  CHECK(summary_of(dir / "two")["notes"].dump().find("initial_state: the cells' states of") != std::string::npos);
  check_same_outputs(dir / "one", dir / "two");
  // The independent reference: the branch's first sample (t = 0) is the
  // source's at 3 ms, to the bit (the traced cells lie on both ranks).
  const std::string at_3_ms = trace_row_at(testing::read_file(dir / "source" / "traces.csv"), 3);
  REQUIRE_FALSE(at_3_ms.empty());
  CHECK(trace_row_at(testing::read_file(dir / "two" / "traces.csv"), 0) == at_3_ms);

  // A checkpoint written split over 2 ranks (each rank's cells in its
  // part), in one process and split over 3: the same outputs again.
  json from_split = branch;
  from_split["initial_state"]["from"] = (dir / "source_two").string();
  std::ofstream(dir / "from_split.json") << from_split.dump();
  REQUIRE(run("", dir / "from_split.json", dir / "from_split_one") == 0);
  check_same_outputs(dir / "one", dir / "from_split_one");
  REQUIRE(run(testing::mpirun(3), dir / "from_split.json", dir / "from_split_three") == 0);
  check_same_outputs(dir / "one", dir / "from_split_three");
}

TEST_SUITE_END();
