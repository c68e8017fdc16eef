// A sweep (docs/guide/sweeps.md): a manifest run over the Cartesian product
// of parameter values (and tissue seeds), each point into DIR/run_<k>/, then
// tabulated (study/sweep_table.hpp). The engine of `fibrodem sweep` and of
// the Python module's fibrodem.sweep.
//
// Points run on a pool of `jobs` workers, each point by the runner chosen
// (study/sweep_point.hpp: a child process of a `fibrodem` executable, or in
// this process). Resumable: a point completed before with the same manifest
// is kept, not run again.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "study/sweep_point.hpp"
#include "study/sweep_table.hpp"

namespace fibrodem {

// Reads the sweep file at `file` (its manifest relative to it), `overrides`
// (PATH=VALUE, as --set) after its own `set`. ManifestError as read_sweep.
SweepFile load_sweep_file(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

// Where a sweep goes without --out: out/sweep_<manifest name>.
std::filesystem::path default_sweep_dir(const SweepFile& sweep);

struct SweepOptions {
  std::filesystem::path out;  // the sweep's folder (required)
  PointRunner runner;
  unsigned jobs = 0;          // workers; 0: one per core
  bool overwrite = false;     // run every point again, even those completed before
  bool report = true;         // the sweep's report.html and its points'
  // Called after each point (from a worker, one call at a time): its index
  // and its outcome.
  std::function<void(std::size_t k, const SweepRun& point)> on_point_done;
  // Before each point: true stops the sweep there (points not started are
  // "interrupted", not run). Null: never. The Python module stops on Ctrl-C.
  std::function<bool()> stop_requested;
};

// Every point of the sweep, not run yet (status empty).
std::vector<SweepRun> sweep_points(const SweepFile& sweep);

// Runs the points whose indices are in `which` (an MPI rank's share; every
// point for a sweep alone) into options.out/run_<k>/, filling runs[k].
void run_sweep_points(const SweepFile& sweep, std::vector<SweepRun>& runs, const std::vector<std::size_t>& which,
                      const SweepOptions& options);

struct SweepResult {
  std::filesystem::path dir;
  std::vector<SweepRun> runs;                     // sweep.csv's rows, in order
  std::vector<GridPointStatistics> statistics;   // over the seeds (sweep_stats.csv) when seeded
  std::string markdown;                           // sweep.md
  std::size_t reused = 0;                         // points completed before, kept
  bool all_completed() const;
};

// Runs every point, then writes the tables (and report.html if options.report).
SweepResult run_sweep(const SweepFile& sweep, const SweepOptions& options);

// The tables of runs already run (all of them, e.g. gathered from MPI ranks).
SweepResult tabulate_sweep(const SweepFile& sweep, std::vector<SweepRun> runs, const SweepOptions& options);

}  // namespace fibrodem
