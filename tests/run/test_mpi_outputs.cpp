// What a run split over MPI ranks writes beyond its biomarkers and traces
// (docs/guide/parallel.md): output.snapshots (rank 0 gathers every cell's V at
// each snapshot time), output.reentry (rank 0 gathers every cell's V at
// each sample and measures at the end) and settle (the coupled tissue
// stepped split before t = 0). With a fixed step and explicit coupling a split run
// computes one process's potentials bit for bit (docs/guide/parallel.md,
// Results), so the reference here is the same scene run in one process:
// the same bytes.
#include <doctest/doctest.h>

#include <filesystem>
#include <set>

#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");
namespace fs = std::filesystem;

namespace {

std::set<std::string> file_names(const fs::path& dir, const std::string& prefix) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().rfind(prefix, 0) == 0) names.insert(entry.path().filename().string());
  return names;
}

// The note summary.json gives of the settle (V's range at t = 0 and its last change).
std::string settle_note(const fs::path& run) {
  const json summary = json::parse(testing::read_file(run / "summary.json"));
  for (const auto& note : summary["notes"])
    if (note.get<std::string>().rfind("settle: the coupled tissue", 0) == 0) return note.get<std::string>();
  return "";
}

}  // namespace

TEST_CASE("mpirun -n 2: output.snapshots of a split run are one process's files") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_snapshots");
  // The wave starts at 2 ms and crosses the sheet's 1.5 mm in about 1.4 ms
  // (106 cm/s): the frames at 3 and 4 ms catch it mid-sheet, where V
  // differs from cell to cell (a cell placed wrong would show).
  json m = testing::split_sheet_planar_wave(5);
  m["output"]["snapshots"] = {{"every_ms", 1}, {"from_ms", 2}, {"png", true}, {"vtk", true}};
  m["output"]["vtk_format"] = "xml";
  m["output"]["maps"] = true;
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  CHECK(json::parse(testing::read_file(dir / "two" / "summary.json"))["mpi_ranks"] == 2);

  const std::set<std::string> frames = file_names(dir / "one", "snapshot_");
  // 2, 3, 4 and 5 ms, each a PNG and a VTK XML file.
  REQUIRE(frames.size() == 8);
  CHECK(frames.count("snapshot_00003.000_ms.vtp") == 1);
  CHECK(file_names(dir / "two", "snapshot_") == frames);
  for (const auto& name : frames) {
    INFO(name);
    CHECK(testing::read_file(dir / "two" / name) == testing::read_file(dir / "one" / name));
  }
  CHECK(testing::read_file(dir / "two" / "snapshots.pvd") == testing::read_file(dir / "one" / "snapshots.pvd"));
  // Rank 0 drew and wrote them from the particles' imprint (io/tissue_imprint.hpp),
  // the maps' VTK file too; the activation map is drawn without antialiasing.
  CHECK(testing::read_file(dir / "two" / "run.log").find("rank 0 keeps the imprint of the tissue's") !=
        std::string::npos);
  CHECK(testing::read_file(dir / "two" / "maps.vtp") == testing::read_file(dir / "one" / "maps.vtp"));
  CHECK(fs::file_size(dir / "two" / "activation_map.png") > 0);
  // The premise: the frames show a moving wave, not a tissue at rest.
  CHECK(testing::read_file(dir / "one" / "snapshot_00003.000_ms.vtp") !=
        testing::read_file(dir / "one" / "snapshot_00004.000_ms.vtp"));
}

TEST_CASE("mpirun -n 3: a fibrotic sheet built cell by cell on every rank gives one process's files") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_cells_alone");
  // fibrotic_sheet builds its cells without their particles on every rank
  // of a run without mechanics (TissueBuilder::build_cells), rank 0 making
  // the particles' imprint from the builder's particles one by one: the
  // pictures and VTK files are one process's, drawn from the whole tissue.
  // Fibroblasts and collagen voids, so that the cells' numbers skip slots
  // and the types differ; a snapshot at 3 ms catches the wave mid-sheet.
  json m = testing::split_fibrotic_sheet_planar_wave(4, "collagen");
  // Ranks 1 and 2 hold part of the cell graph (Simulation's
  // build_part_of_graph): a coupling region over the sheet's right half,
  // which they check as the whole graph goes by and take in their rows.
  m["coupling"]["regions"] =
      json::array({{{"shape", "rectangle"}, {"x_mm", {0.25, 1}}, {"y_mm", {-1, 2}}, {"scale", 0.5}}});
  m["output"]["snapshots"] = {{"every_ms", 1}, {"from_ms", 3}, {"png", true}, {"vtk", true}};
  m["output"]["vtk_format"] = "xml";
  m["output"]["maps"] = true;
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(3), dir / "scene.json", dir / "three") == 0);
  CHECK(testing::read_file(dir / "three" / "run.log").find("every rank built the cells without them") !=
        std::string::npos);
  const std::set<std::string> frames = file_names(dir / "one", "snapshot_");
  REQUIRE(frames.size() == 4);  // 3 and 4 ms, a PNG and a VTK XML file each
  for (const auto& name : frames) {
    INFO(name);
    CHECK(testing::read_file(dir / "three" / name) == testing::read_file(dir / "one" / name));
  }
  for (const char* name : {"maps.vtp", "biomarkers.csv", "traces.csv"}) {
    INFO(name);
    CHECK(testing::read_file(dir / "three" / name) == testing::read_file(dir / "one" / name));
  }
  // The premise: the wave is mid-sheet at 3 ms (V differs from cell to cell).
  CHECK(testing::read_file(dir / "one" / "snapshot_00003.000_ms.vtp") !=
        testing::read_file(dir / "one" / "snapshot_00004.000_ms.vtp"));

  // A region off the sheet holds no junction: the run stops at set-up
  // (every rank refuses it, rank 0 from the whole graph, the others from the
  // graph as it went by: tests/coupling/test_coupling_regions.cpp; the
  // first to stop ends the job, so the others may not get to say so).
  m["coupling"]["regions"][0]["x_mm"] = {5, 6};
  std::ofstream(dir / "off.json") << m.dump();
  CHECK(testing::run_fibrodem(testing::mpirun(3), "run " + (dir / "off.json").string() + " --out " +
                                                      (dir / "off").string(),
                              dir / "off.txt") != 0);
  CHECK(testing::read_file(dir / "off.txt").find("coupling.regions[0]: holds no junction") != std::string::npos);
}

TEST_CASE("mpirun -n 2: settle split over ranks gives one process's outputs") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_settle");
  json m = testing::split_sheet_planar_wave(12);
  m["output"]["traces"][0]["every_ms"] = 0.5;
  std::ofstream(dir / "unsettled.json") << m.dump();
  m["settle"] = {{"ms", 20}};
  std::ofstream(dir / "settled.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "settled.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "settled.json", dir / "two") == 0);
  REQUIRE(testing::run_scene("", dir / "unsettled.json", dir / "unsettled") == 0);

  for (const char* file : {"biomarkers.csv", "traces.csv"}) {
    INFO(file);
    CHECK(testing::read_file(dir / "two" / file) == testing::read_file(dir / "one" / file));
  }
  // V's range at t = 0 and its change over the settle's last tenth, measured
  // over every rank's cells: one process's numbers.
  const std::string note = settle_note(dir / "one");
  REQUIRE_FALSE(note.empty());
  CHECK(settle_note(dir / "two") == note);
  // The premise: the settle changed where the cells start (the fibroblasts
  // coupled to myocytes rest below their own rest, run/simulation_settle.cpp).
  CHECK(testing::read_file(dir / "unsettled" / "traces.csv") != testing::read_file(dir / "one" / "traces.csv"));
}

TEST_CASE("mpirun -n 2: output.reentry of a split run is one process's") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_reentry");
  // Samples every 0.125 ms on the 0.01 ms step: every other sample lies
  // halfway through a step, so the interpolation between a step's ends is
  // exercised as well as the samples on a step's end. tau_ms is a whole
  // multiple of every_ms (docs/topics/arrhythmia.md). By 8 ms the wave (stimulus at
  // 2 ms) has activated every myocyte (checked below), so the beat maps hold
  // activation times that differ from cell to cell.
  // The maps' VTK file in both formats: legacy (rank 0 keeps the particles
  // to write it) and XML (rank 0 writes it, and draws, from the imprint).
  std::string format;
  SUBCASE("legacy VTK") { format = "legacy"; }
  SUBCASE("VTK XML") { format = "xml"; }
  json m = testing::split_sheet_planar_wave(8);
  m["output"]["reentry"] = {{"every_ms", 0.125}, {"from_ms", 0.5}, {"tau_ms", 1}};
  m["output"]["vtk_format"] = format;
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);

  const json one = json::parse(testing::read_file(dir / "one" / "summary.json"));
  const json two = json::parse(testing::read_file(dir / "two" / "summary.json"));
  CHECK(two["mpi_ranks"] == 2);
  REQUIRE(one.contains("reentry"));
  REQUIRE(two.contains("reentry"));
  CHECK(two["reentry"].dump() == one["reentry"].dump());
  // The premise: the wave was sampled (a beat map drawn from its
  // activations, every myocyte reached, at times spread over milliseconds).
  CHECK(one["reentry"]["beat_maps_drawn"].get<int>() >= 1);
  const json& beat = one["reentry"]["beats"][0];
  CHECK(beat["reached"] == beat["counted"]);
  CHECK(beat["last_activation_ms"].get<double>() - beat["first_activation_ms"].get<double>() > 1);

  std::set<std::string> files = file_names(dir / "one", "activation_beat_");
  CHECK(!files.empty());
  const bool xml = format == "xml";
  CHECK(testing::read_file(dir / "two" / "run.log")
            .find(xml ? "rank 0 keeps the imprint" : "rank 0 keeps the tissue's particles: the legacy VTK") !=
        std::string::npos);
  for (const char* name : {"phase_singularities.csv", "dominant_frequency_map.png", "phase_singularity_density_map.png",
                           xml ? "reentry_maps.vtp" : "reentry_maps.vtk"})
    files.insert(name);
  for (const auto& name : files) {
    INFO(name);
    REQUIRE(fs::exists(dir / "one" / name));
    CHECK(testing::read_file(dir / "two" / name) == testing::read_file(dir / "one" / name));
  }
  // V at the samples as the maps hold it: a cell placed wrong, or a sample
  // taken at another time on one rank, would show in the activation times.
  CHECK(file_names(dir / "two", "activation_beat_") == file_names(dir / "one", "activation_beat_"));
}

TEST_SUITE_END();
