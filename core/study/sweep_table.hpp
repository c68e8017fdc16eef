// A sweep's results: one row per run (sweep.csv, sweep.md), and with tissue
// seeds, per grid point the mean, SD and 95 % confidence interval over the
// seeds of each metric (sweep_stats.csv and in sweep.md), and sweep.png (each
// metric against the first grid axis, error bars over the seeds).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "measure/sample_statistics.hpp"
#include "scene/sweep_file.hpp"

namespace fibrodem {

struct SweepRun {
  SweepValues values;  // grid path -> value (and "seed" with seeds)
  json summary;        // the run's summary.json (null if it wrote none)
  std::string status;  // completed | failed | interrupted | crashed
  std::string error;
  bool reused = false;  // completed by an earlier sweep with the same manifest
};

// With seeds, per grid point (the runs of its seeds): its values without the
// seed, how many of its runs completed, and per metric of summary_metrics()
// (in that order) the summary over its completed runs; without seeds, one
// "grid point" per run. sweep_stats.csv holds these numbers.
struct GridPointStatistics {
  SweepValues values;
  std::size_t completed = 0;
  std::vector<SampleSummary> metrics;
};
std::vector<GridPointStatistics> grid_point_statistics(const SweepFile& sweep, const std::vector<SweepRun>& runs);

// Writes sweep.csv, sweep.md and (with seeds) sweep_stats.csv, sweep.png
// and (if `report`) report.html; returns sweep.md's text.
std::string write_sweep_tables(const SweepFile& sweep, const std::vector<SweepRun>& runs,
                               const std::filesystem::path& dir, bool report = true);

}  // namespace fibrodem
