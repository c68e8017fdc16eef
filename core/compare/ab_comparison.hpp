// A/B comparison of two runs (docs/guide/compare.md): per-cell-type mean
// biomarkers side by side with differences and relative differences (Markdown
// and CSV), and the traces of both on a common time base.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/plot_png.hpp"
#include "measure/run_record.hpp"

namespace fibrodem {

struct ComparisonRow {
  std::string type, metric;
  double a = 0, b = 0;
  double diff() const { return b - a; }
  double relative_diff() const;  // (b - a) / |a|; NaN when a == 0
};

std::vector<ComparisonRow> compare_biomarkers(const RunRecord& a, const RunRecord& b);

// Writes comparison.md, comparison.csv and traces.csv (t_ms, then A:COL and B:COL
// for the columns both runs traced, linearly interpolated onto a grid over the
// common time span at the finer of the two sampling intervals).
void write_comparison(const RunRecord& a, const RunRecord& b, const std::filesystem::path& dir);

// The columns both runs traced (the first kMostTracePanels), one panel each,
// A and B overlaid: traces.png and the comparison's report.html.
inline constexpr std::size_t kMostTracePanels = 6;
std::vector<PlotPanel> comparison_trace_panels(const RunRecord& a, const RunRecord& b);

std::string comparison_markdown(const RunRecord& a, const RunRecord& b);

}  // namespace fibrodem
