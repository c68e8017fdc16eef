// Helpers of the tests that start fibrodem under mpirun: whether mpirun is
// there, its command line, `fibrodem run` of a scene file under it, and the
// sheet the split-run tests share.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/scenes.hpp"

namespace fibrodem::testing {

inline bool have_mpirun() { return std::system("command -v mpirun > /dev/null 2>&1") == 0; }

// Ends the test case, saying so, where this machine has no mpirun (the
// split-run tests need Open MPI's launcher; scripts/setup.sh installs it).
#define FIBRODEM_SKIP_WITHOUT_MPIRUN()                                          \
  do {                                                                        \
    if (!::fibrodem::testing::have_mpirun()) {                                \
      MESSAGE("skipped: mpirun not found (scripts/setup.sh installs openmpi-bin)"); \
      return;                                                                 \
    }                                                                         \
  } while (0)

// (CI runs as root, which OpenMPI refuses unless told; its own allocations
// that it never frees are not ours to report under AddressSanitizer.)
inline std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n " +
         std::to_string(ranks) + " --oversubscribe ";
}

// `fibrodem ARGS` under the launcher ("" for none), its output into `log`;
// the exit status (128 + the signal if one ended it).
inline int run_fibrodem(const std::string& launcher, const std::string& args, const std::filesystem::path& log) {
  const std::string command =
      launcher + std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// `fibrodem run SCENE --out OUT --quiet --no-report` under the launcher,
// its output into OUT.txt.
inline int run_scene(const std::string& launcher, const std::filesystem::path& scene,
                     const std::filesystem::path& out) {
  return run_fibrodem(launcher, "run " + scene.string() + " --out " + out.string() + " --quiet --no-report",
                      out.string() + ".txt");
}

// A 0.6 x 1.5 mm sheet of myocytes in series with fibroblasts (329 cells),
// stimulated along its upper edge: a planar wave down the sheet (about
// 106 cm/s), through repolarisation (APD90 about 240 ms) by `duration_ms`.
// A trace of V in cells far apart (on different ranks).
inline json split_sheet_planar_wave(double duration_ms) {
  json m = json::parse(R"({"fibrodem": 1, "name": "planar", "seed": 4,
    "tissue": {"builder": "in_series", "width_mm": 0.6, "height_mm": 1.5, "fm_ratio": 0.2},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_f_nS": 1},
    "stimulus": [{"target": {"y_min_frac": 0.9, "type": "myocyte"}, "start_ms": 2, "duration_ms": 2,
                  "amplitude_pA": 8000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": [{"cells": [0, 150, 300], "variables": ["V"], "every_ms": 1}]}})");
  m["duration_ms"] = duration_ms;
  return m;
}

// The same wave on a 0.5 x 1.5 mm fibrotic_sheet with 15 % patchy fibrosis
// `as` "fibroblasts" or "collagen" (collagen as particles): a builder that
// makes its cells alone, whose split ranks other than 0 hold part of the
// cell graph; the cells' numbers skip the fibrotic slots. Stimulated along
// its lower edge, traced in cells far apart.
inline json split_fibrotic_sheet_planar_wave(double duration_ms, const std::string& as) {
  json m = split_sheet_planar_wave(duration_ms);
  json fibrosis = {{"density", 0.15}, {"pattern", "patchy"}, {"correlation_length_mm", 0.1}, {"as", as}};
  if (as == "collagen") fibrosis["collagen"] = "particles";
  m["tissue"] = {{"builder", "fibrotic_sheet"}, {"width_mm", 0.5}, {"length_mm", 1.5}, {"fibrosis", fibrosis}};
  m["stimulus"][0]["target"] = {{"y_max_frac", 0.1}, {"type", "myocyte"}};
  m["output"]["traces"][0]["cells"] = {0, 90, 180};
  return m;
}

}  // namespace fibrodem::testing
