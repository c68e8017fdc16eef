// sweep/report.html: a sweep's tables and its metrics against the grid axes,
// from what study/sweep_table has computed (the same rows as sweep.md, the
// same panels as sweep.png, drawn as SVG), with links to each run's report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/plot_png.hpp"

namespace fibrodem {

struct ReportTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

struct SweepReportContent {
  std::string title;
  ReportTable runs;                    // one row per run (sweep.csv)
  ReportTable statistics;              // per grid point over the seeds; empty without seeds
  std::vector<PlotPanel> panels;       // each metric against the first grid axis
  std::string plot_title;
  std::vector<std::string> failures;   // runs that did not complete, one line each
  std::vector<std::string> run_dirs;   // relative to the sweep's folder, in run order
};

// Writes dir/report.html; returns its path. Throws std::runtime_error if it
// cannot be written.
std::filesystem::path write_sweep_report(const std::filesystem::path& dir, const SweepReportContent& content);

}  // namespace fibrodem
