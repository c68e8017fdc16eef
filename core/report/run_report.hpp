// report.html of a run's folder, written from what is on disk alone
// (summary.json, traces.csv, biomarkers.csv, run.log, the PNG pictures), so
// it works for a folder of a completed, failed, interrupted or killed run, at
// the end of a run or later (`fibrodem report DIR`). Whatever is missing is
// said in the report, not an error.
#pragma once

#include <filesystem>

namespace fibrodem {

// Writes dir/report.html; returns its path. Throws std::runtime_error if dir
// is not a folder or the page cannot be written.
std::filesystem::path write_run_report(const std::filesystem::path& dir);

}  // namespace fibrodem
