// compare/report.html: A and B side by side, from what core/compare computes
// (the difference table of compare_biomarkers, the trace panels of
// comparison_trace_panels, drawn as SVG) and the pictures the two runs left
// in their folders (tissue, activation map), with links to their own reports.
#pragma once

#include <filesystem>
#include <string>

#include "measure/run_record.hpp"

namespace fibrodem {

struct CompareReportInput {
  const RunRecord& a;
  const RunRecord& b;
  std::filesystem::path a_dir, b_dir;  // the runs' folders, relative to the comparison's
  std::string paired_markdown;         // with --seeds: paired.md's text; empty otherwise
};

// Writes dir/report.html; returns its path.
std::filesystem::path write_compare_report(const std::filesystem::path& dir, const CompareReportInput& input);

}  // namespace fibrodem
