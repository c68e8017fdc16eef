// The shared libraries the command line loads: Cairo (pictures) and Open MPI
// (mpirun) are in modules opened on first use (core/util/runtime_module.hpp),
// so a run that draws nothing and was not launched by mpirun loads neither
// (docs/topics/performance.md#start-up). What a process loads is read from glibc's
// loader trace (LD_DEBUG=libs: one "calling init: FILE" line per library it
// initialises, the executable's own needs and every dlopen alike).
#include <doctest/doctest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
using fibrodem::testing::read_file;
using fibrodem::testing::run_fibrodem;
using fibrodem::testing::scratch_dir;
namespace fs = std::filesystem;

namespace {

// The file names (no folder) of the libraries the loader initialised, from
// an LD_DEBUG=libs trace.
std::set<std::string> initialised_libraries(const std::string& trace) {
  std::set<std::string> names;
  std::istringstream lines(trace);
  const std::string marker = "calling init: ";
  for (std::string line; std::getline(lines, line);)
    if (const auto at = line.find(marker); at != std::string::npos)
      names.insert(fs::path(line.substr(at + marker.size())).filename().string());
  return names;
}

bool loaded(const std::set<std::string>& libraries, const std::string& name_start) {
  for (const auto& name : libraries)
    if (name.rfind(name_start, 0) == 0) return true;
  return false;
}

fs::path write_scene(const fs::path& dir) {
  json manifest = fibrodem::testing::passive_cell_manifest();
  manifest["duration_ms"] = 5;
  std::ofstream(dir / "scene.json") << manifest.dump(1);
  return dir / "scene.json";
}

}  // namespace

TEST_CASE("start-up: a run without pictures, not under mpirun, loads neither Cairo nor Open MPI") {
  const fs::path dir = scratch_dir("start_up_no_pictures");
  const fs::path scene = write_scene(dir);
  REQUIRE(run_fibrodem("LD_DEBUG=libs ", "run " + scene.string() + " --out " + (dir / "out").string() +
                                             " --quiet --no-report", dir / "log.txt") == 0);
  const auto libraries = initialised_libraries(read_file(dir / "log.txt"));
  // The trace is read right: the C++ runtime and the scene's plugin are in it.
  CHECK(loaded(libraries, "libstdc++.so"));
  CHECK(loaded(libraries, "libfibrodem_passive_fibroblast.so"));
  CHECK_FALSE(loaded(libraries, "libcairo"));
  CHECK_FALSE(loaded(libraries, "libpng"));
  CHECK_FALSE(loaded(libraries, "libfibrodem-drawing"));
  CHECK_FALSE(loaded(libraries, "libmpi"));
  CHECK_FALSE(loaded(libraries, "libopen-pal"));
  CHECK_FALSE(loaded(libraries, "libfibrodem-mpi"));
}

TEST_CASE("start-up: the first picture opens the drawing module, and Cairo with it") {
  const fs::path dir = scratch_dir("start_up_pictures");
  const fs::path scene = write_scene(dir);
  // report.html draws its trace plots (SVG, through Cairo).
  REQUIRE(run_fibrodem("LD_DEBUG=libs ", "run " + scene.string() + " --out " + (dir / "out").string() + " --quiet",
                       dir / "log.txt") == 0);
  const auto libraries = initialised_libraries(read_file(dir / "log.txt"));
  CHECK(loaded(libraries, "libfibrodem-drawing.so"));
  CHECK(loaded(libraries, "libcairo"));
  CHECK_FALSE(loaded(libraries, "libmpi"));
  CHECK(read_file(dir / "out" / "report.html").find("<svg") != std::string::npos);
}

TEST_CASE("start-up: a missing module is an error naming the module, the folders searched and the need") {
  // A copy of the executable away from the build: no module beside it, its
  // parent or ../lib/fibrodem (its plugins are still found through the path).
  const fs::path dir = scratch_dir("start_up_missing_module");
  fs::create_directories(dir / "bin");
  fs::copy_file(fs::path(FIBRODEM_BINARY_DIR) / "fibrodem", dir / "bin" / "fibrodem");
  const std::string plugins = "FIBRODEM_PLUGIN_PATH=" + std::string(FIBRODEM_BINARY_DIR) + "/plugins ";
  const auto fibrodem_alone = [&](const std::string& environment, const std::string& args, const fs::path& log) {
    const int status = std::system((plugins + environment + (dir / "bin" / "fibrodem").string() + " " + args + " > " +
                                    log.string() + " 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  };

  SUBCASE("drawing: `fibrodem plot` fails and says which module is missing where") {
    std::ofstream(dir / "plot.json") << R"({"panels": [{"title": "a", "x_label": "x", "y_label": "y",
      "log_x": false, "log_y": false, "series": [{"label": "s", "x": [0, 1], "y": [0, 1]}]}]})";
    CHECK(fibrodem_alone("", "plot " + (dir / "plot.json").string() + " --out " + (dir / "plot.png").string(),
                         dir / "plot.txt") != 0);
    const std::string message = read_file(dir / "plot.txt");
    CHECK(message.find("libfibrodem-drawing.so is missing") != std::string::npos);
    CHECK(message.find("needed to draw pictures and plots") != std::string::npos);
    CHECK(message.find((dir / "bin").string()) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "plot.png"));
    // The same copy finds it through FIBRODEM_MODULE_PATH.
    CHECK(fibrodem_alone("FIBRODEM_MODULE_PATH=" + std::string(FIBRODEM_BINARY_DIR) + " ",
                         "plot " + (dir / "plot.json").string() + " --out " + (dir / "plot.png").string(),
                         dir / "plot_found.txt") == 0);
    CHECK(fs::file_size(dir / "plot.png") > 0);
  }

  SUBCASE("MPI: a process that mpirun's environment says is a rank fails before writing anything") {
    if (!fs::exists(fs::path(FIBRODEM_BINARY_DIR) / "libfibrodem-mpi.so")) {
      MESSAGE("skipped: this build has no MPI module (no libopenmpi-dev)");
      return;
    }
    // Open MPI's variable alone (no mpirun): the process takes itself for
    // rank of two and needs the MPI module to meet the other.
    const fs::path scene = write_scene(dir);
    CHECK(fibrodem_alone("OMPI_COMM_WORLD_SIZE=2 ",
                         "run " + scene.string() + " --out " + (dir / "out").string() + " --quiet --no-report",
                         dir / "run.txt") != 0);
    const std::string message = read_file(dir / "run.txt");
    INFO(message);
    CHECK(message.find("libfibrodem-mpi.so is missing") != std::string::npos);
    CHECK(message.find("needed under mpirun") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out" / "summary.json"));
  }
}

TEST_CASE("start-up: --help lists every subcommand, and a subcommand's options parse") {
  const fs::path dir = scratch_dir("start_up_subcommands");
  REQUIRE(run_fibrodem("", "--help", dir / "help.txt") == 0);
  const std::string help = read_file(dir / "help.txt");
  for (const char* name : {"run", "resume", "report", "validate", "compare", "sweep", "vulnerable-window",
                           "restitution", "plugins", "plot", "check-plugin", "new-model", "bench", "import-cellml",
                           "schema"})
    CHECK_MESSAGE(help.find(std::string("  ") + name + " ") != std::string::npos, name);
  REQUIRE(run_fibrodem("", "--version", dir / "version.txt") == 0);
  CHECK(read_file(dir / "version.txt") == std::string("fibrodem ") + FIBRODEM_VERSION + "\n");
  // A subcommand's own options still parse, and its errors still name them.
  REQUIRE(run_fibrodem("", "schema --json sweep", dir / "schema.txt") == 0);
  CHECK(read_file(dir / "schema.txt").find("\"$schema\"") != std::string::npos);
  CHECK(run_fibrodem("", "run", dir / "run.txt") != 0);
  CHECK(read_file(dir / "run.txt").find("manifest is required") != std::string::npos);
  CHECK(run_fibrodem("", "rnu x.json", dir / "typo.txt") != 0);
}
