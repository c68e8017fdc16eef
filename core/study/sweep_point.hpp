// Running one point of a sweep into its folder, by one of two runners:
// - a child process (`EXE run manifest.json --set solver.threads=1 ...` of a
//   given fibrodem executable): a point that crashes (a segfault in a user's
//   plugin) cannot take the others down; its status is "crashed" with the
//   signal;
// - in this process (one Simulation, single-threaded): no executable needed
//   (the Python module without a `fibrodem` beside it); a crash takes the
//   whole sweep down.
// Both write the same folder (manifest.json, then what `fibrodem run` writes)
// and run the same single-threaded simulation, so their numbers are equal.
// A point whose folder holds a completed summary.json of the same manifest
// (its manifest.json, byte for byte) is not run again unless `overwrite`.
#pragma once

#include <filesystem>
#include <variant>
#include <vector>

#include "study/sweep_table.hpp"

namespace fibrodem {

struct ChildProcessRunner {
  std::filesystem::path executable;  // a `fibrodem` (the command line passes its own)
};

struct InProcessRunner {
  // Where plugins are searched after the manifest's plugin_path; empty: as
  // `fibrodem run` searches ($FIBRODEM_PLUGIN_PATH, then beside this executable).
  std::vector<std::filesystem::path> plugin_search_path;
};

// (In-process by default: it needs nothing from the caller.)
using PointRunner = std::variant<InProcessRunner, ChildProcessRunner>;

// Runs `point` (its values set) into `dir` and fills its summary, status,
// error and reused; never throws (a bad point is "failed" with its error).
// `report`: the point's report.html.
void run_sweep_point(const SweepFile& sweep, SweepRun& point, const std::filesystem::path& dir,
                     const PointRunner& runner, bool overwrite, bool report);

}  // namespace fibrodem
