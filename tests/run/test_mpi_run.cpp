// `fibrodem run` and `fibrodem resume` under mpirun (run/over_ranks.hpp):
// with one rank a run as without mpirun; with several, a scene the ranks
// cannot share stops on every rank before anything is written.
// (tests/tissue/test_mpi_tissue.cpp runs a scene they share.)
#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>

#include "run/over_ranks.hpp"
#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");

namespace {

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

json strand_manifest() {
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "strand"}, {"cells", 6}, {"type", "fibroblast"}};
  m["duration_ms"] = 5;
  return m;
}

}  // namespace

TEST_CASE("over ranks: every unsupported part of a scene is named") {
  json m = strand_manifest();
  // A fixed-step method with explicit coupling, biomarkers, traces of
  // states, snapshots, re-entry, settle and checkpoints: split.
  m["output"]["snapshots"] = {{"every_ms", 1}};
  m["output"]["reentry"] = {{"every_ms", 1}};
  m["output"]["checkpoint"] = {{"every_ms", 1}};
  m["settle"] = {{"ms", 10}};
  CHECK(unsupported_over_ranks(parse_scene(m)).empty());
  // Contraction, mechano-electric feedback and the mechanics (the DEM split
  // too, or on rank 0) run split.
  m["cells"]["myocyte"] = {{"model", "colman"}, {"myofilament", "rice"}};
  m["effects"] = {"electrophysiology", "coupling", "contraction", "mechano_electric_feedback", "mechanics"};
  CHECK(unsupported_over_ranks(parse_scene(m)).empty());
  m["solver"] = {{"method", "cvode"}};
  const std::vector<std::string> named = unsupported_over_ranks(parse_scene(m));
  REQUIRE(named.size() == 1);
  CHECK(named[0] == "solver.method \"cvode\" (only \"adaptive\" and the fixed-step methods run split)");
  const std::string message = refusal_over_ranks("run", 3, {"first", "second"});
  CHECK(message.find("`fibrodem run` under mpirun with 3 ranks") != std::string::npos);
  CHECK(message.find("unsupported: first; second.") != std::string::npos);
  CHECK(message.find("mpirun -n 3 fibrodem sweep") != std::string::npos);
  // auto chooses the adaptive method for a tissue (integrate/method_choice.hpp),
  // which runs split, as does the implicit coupling of a fixed step.
  json automatic = strand_manifest();
  automatic["tissue"]["cells"] = 40;
  automatic["solver"] = {{"method", "auto"}};
  CHECK(unsupported_over_ranks(parse_scene(automatic)).empty());
  // On 16 cells or fewer it chooses CVODE, which does not.
  automatic["tissue"]["cells"] = 6;
  const std::vector<std::string> chosen = unsupported_over_ranks(parse_scene(automatic));
  REQUIRE(chosen.size() == 1);
  CHECK(chosen[0].find("solver.method \"auto\", which chose \"cvode\" (name \"adaptive\"") == 0);
  json implicit = strand_manifest();
  implicit["coupling"] = {{"scheme", "implicit"}};
  CHECK(unsupported_over_ranks(parse_scene(implicit)).empty());
}

TEST_CASE("mpirun -n 2 fibrodem run refuses on every rank and writes nothing") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_run_refused");
  json m = strand_manifest();
  m["solver"] = {{"method", "cvode"}};
  std::ofstream(dir / "scene.json") << m.dump();
  const std::string out = (dir / "out").string();
  CHECK(testing::run_fibrodem(testing::mpirun(2), "run " + (dir / "scene.json").string() + " --out " + out, dir / "log.txt") != 0);
  const std::string log = testing::read_file(dir / "log.txt");
  CHECK(count_of(log, "`fibrodem run` under mpirun with 2 ranks") == 2);  // one per rank
  CHECK_FALSE(std::filesystem::exists(dir / "out"));

  // The same scene on one rank runs as without mpirun.
  REQUIRE(testing::run_fibrodem(testing::mpirun(1), "run " + (dir / "scene.json").string() + " --out " + out + " --quiet",
                   dir / "one.txt") == 0);
  CHECK(json::parse(testing::read_file(dir / "out" / "summary.json"))["status"] == "completed");

  // resume over 2 ranks of a run that stopped before its end (its status
  // says so: a completed run has nothing to resume): refused, the folder as
  // it was.
  json stopped = json::parse(testing::read_file(dir / "out" / "summary.json"));
  stopped["status"] = "interrupted";
  std::ofstream(dir / "out" / "summary.json") << stopped.dump();
  const std::string summary = testing::read_file(dir / "out" / "summary.json");
  CHECK(testing::run_fibrodem(testing::mpirun(2), "resume " + out, dir / "resume.txt") != 0);
  const std::string resume_log = testing::read_file(dir / "resume.txt");
  CHECK(count_of(resume_log, "`fibrodem resume` under mpirun with 2 ranks") == 2);
  CHECK(resume_log.find("methods run split). Nothing was written") != std::string::npos);
  CHECK(testing::read_file(dir / "out" / "summary.json") == summary);
}

TEST_CASE("mpirun -n 2 fibrodem validate: each rank's memory, for its own cells") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_validate");
  json m = strand_manifest();
  m["tissue"]["cells"] = 40;
  m["solver"] = {{"method", "auto"}};  // (the adaptive method on 40 cells: split)
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_fibrodem(testing::mpirun(2), "validate " + (dir / "scene.json").string(), dir / "log.txt") == 0);
  const std::string log = testing::read_file(dir / "log.txt");
  CHECK(count_of(log, ": valid. 40 cells") == 1);  // rank 0 tells
  CHECK(log.find("split over 2 MPI ranks, each rank's estimate:") != std::string::npos);
  // Each rank's biomarkers are its own cells', together the tissue's; rank
  // 0 keeps the tissue's particles (it draws), rank 1 none.
  const auto number_after = [&](const std::string& from, const std::string& what) {
    const std::size_t line = log.find(from);
    REQUIRE(line != std::string::npos);
    const std::size_t at = log.find(what, line);
    REQUIRE(at != std::string::npos);
    return std::stol(log.substr(at + what.size()));
  };
  const long own_0 = number_after("  rank 0: memory ~", "biomarkers: "),
             own_1 = number_after("  rank 1: memory ~", "biomarkers: ");
  CHECK(own_0 + own_1 == 40);
  CHECK(own_0 > 0);
  CHECK(own_1 > 0);
  CHECK(number_after("  rank 0: memory ~", "tissue: ") == 40);
  CHECK(number_after("  rank 1: memory ~", "tissue: ") == 0);
  CHECK(log.find("imprint") == std::string::npos);

  // With VTK XML files rank 0 keeps the particles' imprint instead (io/tissue_imprint.hpp).
  m["output"]["vtk_format"] = "xml";
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_fibrodem(testing::mpirun(2), "validate " + (dir / "scene.json").string(), dir / "log.txt") == 0);
  const std::string xml_log = testing::read_file(dir / "log.txt");
  const std::size_t rank_0 = xml_log.find("  rank 0: memory ~"), rank_1 = xml_log.find("  rank 1: memory ~");
  REQUIRE(rank_0 != std::string::npos);
  REQUIRE(rank_1 != std::string::npos);
  const std::string line_0 = xml_log.substr(rank_0, xml_log.find('\n', rank_0) - rank_0);
  CHECK(line_0.find("tissue: 0 particles") != std::string::npos);
  CHECK(line_0.find("the particles' imprint") != std::string::npos);
  CHECK(xml_log.substr(rank_1).find("imprint") == std::string::npos);
}

TEST_SUITE_END();
