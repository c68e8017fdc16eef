// `fibrodem` bounds libgomp's spinning (GOMP_SPINCOUNT=10000, which libgomp
// reads only as it loads) by starting itself again, and only where a team of
// threads may run: not for a single cell under solver.threads "auto", which
// never opens a parallel region, yet for a strand. libgomp prints the count
// it read once per load when OMP_DISPLAY_ENV=verbose, so the number of such
// lines is the number of times the program was loaded.
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// The spin counts libgomp printed, in order, for `arguments` run with none of
// OMP_WAIT_POLICY, GOMP_SPINCOUNT, OMP_PLACES and OMP_PROC_BIND set but
// those `environment` sets (NAME=VALUE ...).
std::vector<std::string> spin_counts_read(const std::string& arguments, const std::string& environment = "") {
  const std::string command =
      "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u OMP_PLACES -u OMP_PROC_BIND OMP_DISPLAY_ENV=verbose " + environment +
      " " + std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::vector<std::string> counts;
  char line[512];
  while (fgets(line, sizeof line, pipe)) {
    const std::string text = line;
    const auto at = text.find("GOMP_SPINCOUNT = '");
    if (at != std::string::npos) counts.push_back(text.substr(at + 18, text.find('\'', at + 18) - at - 18));
  }
  const int status = pclose(pipe);
  CHECK(WEXITSTATUS(status) == 0);
  return counts;
}

}  // namespace

TEST_CASE("a single cell runs without the restart that bounds OpenMP's spinning, a strand with it") {
  // Only GCC's libgomp prints GOMP_SPINCOUNT (and reads it): a build with
  // another OpenMP runtime (clang's libomp, as the sanitizer builds) has
  // nothing to count here.
  const auto version = spin_counts_read("--version");
  if (version.empty()) {
    MESSAGE("skipped: the OpenMP runtime is not GCC's libgomp");
    return;
  }
  const auto dir = testing::scratch_dir("openmp_spinning");
  const std::string examples = std::string(FIBRODEM_SOURCE_DIR) + "/examples/";
  const auto one_cell = spin_counts_read("run " + examples + "single_cell_colman_ni2017.json --set duration_ms=1 --out " +
                                         (dir / "one_cell").string() + " --quiet --no-report");
  REQUIRE(one_cell.size() == 1);  // loaded once: libgomp's own default, never used
  const auto strand = spin_counts_read("validate " + examples + "strand_colman.json");
  REQUIRE(strand.size() == 2);  // loaded, then started again with the bound
  CHECK(strand[1] == "10000");
  CHECK(version.size() == 1);
}

TEST_CASE("threads the user binds to places are not restarted, which would leave the process one CPU" * doctest::test_suite("threads")) {
  // With OMP_PLACES, or OMP_PROC_BIND other than false, libgomp pins the
  // first thread to a CPU as it loads, and a process started again from it
  // would inherit that CPU alone.
  if (spin_counts_read("--version").empty()) {
    MESSAGE("skipped: the OpenMP runtime is not GCC's libgomp");
    return;
  }
  const std::string strand = "validate " + std::string(FIBRODEM_SOURCE_DIR) + "/examples/strand_colman.json";
  for (const char* binding : {"OMP_PROC_BIND=true", "OMP_PROC_BIND=spread", "OMP_PLACES=cores"}) {
    CAPTURE(binding);
    CHECK(spin_counts_read(strand, binding).size() == 1);
  }
  CHECK(spin_counts_read(strand, "OMP_PROC_BIND=false").size() == 2);
}
