// report.html of a run's folder, written from what is on disk alone
// (summary.json, traces.csv, biomarkers.csv, run.log, the PNG pictures), so
// it works for a folder of a completed, failed, interrupted or killed run, at
// the end of a run or later (`fibrodem report DIR`). Whatever is missing is
// said in the report, not an error.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace fibrodem {

// Writes dir/report.html; returns its path. Throws std::runtime_error if dir
// is not a folder or the page cannot be written.
std::filesystem::path write_run_report(const std::filesystem::path& dir);

// The same page for a run that has its summary in memory (the end of a run,
// which writes summary.json once, after the report): `summary` as
// summary.json would hold it, instead of dir/summary.json.
std::filesystem::path write_run_report(const std::filesystem::path& dir, const nlohmann::json& summary);

}  // namespace fibrodem
