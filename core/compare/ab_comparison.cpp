#include "compare/ab_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "io/csv_writer.hpp"
#include "io/plot_png.hpp"

namespace fibrodem {

namespace {

constexpr const char* kMetrics[] = {"rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms"};

double value_of(const json& means, const std::string& type, const std::string& metric) {
  if (!means.contains(type) || !means[type].contains(metric) || means[type][metric].is_null())
    return std::numeric_limits<double>::quiet_NaN();
  return means[type][metric].get<double>();
}

// Linear interpolation of samples (t, y) at time x (t sorted, x within range).
double interpolate(const std::vector<double>& t, const std::vector<double>& y, double x) {
  const auto it = std::lower_bound(t.begin(), t.end(), x);
  if (it == t.begin()) return y.front();
  if (it == t.end()) return y.back();
  const std::size_t k = static_cast<std::size_t>(it - t.begin());
  const double w = (x - t[k - 1]) / (t[k] - t[k - 1]);
  return y[k - 1] + w * (y[k] - y[k - 1]);
}

double finest_interval(const std::vector<double>& t) {
  double h = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < t.size(); ++k) h = std::min(h, t[k] - t[k - 1]);
  return h;
}

std::string fixed(double x, int digits) { return fixed_decimals(x, digits, "n/a"); }

// (column of a, column of b) for each column both runs traced.
std::vector<std::pair<std::size_t, std::size_t>> shared_columns(const RunRecord& a, const RunRecord& b) {
  std::vector<std::pair<std::size_t, std::size_t>> shared;
  for (std::size_t i = 0; i < a.columns.size(); ++i)
    for (std::size_t j = 0; j < b.columns.size(); ++j)
      if (a.columns[i] == b.columns[j]) shared.emplace_back(i, j);
  return shared;
}

}  // namespace

std::vector<PlotPanel> comparison_trace_panels(const RunRecord& a, const RunRecord& b) {
  std::vector<PlotPanel> panels;
  const auto shared = shared_columns(a, b);
  for (std::size_t k = 0; k < shared.size() && k < kMostTracePanels; ++k) {
    const auto [i, j] = shared[k];
    PlotPanel panel{a.columns[i], "t [ms]", a.columns[i], false, false, {}, {}};
    panel.series.push_back({a.label, a.times_ms, a.samples[i]});
    panel.series.push_back({b.label, b.times_ms, b.samples[j]});
    for (auto& series : panel.series) series.markers = false;  // dense samples: lines alone
    panels.push_back(std::move(panel));
  }
  return panels;
}

double ComparisonRow::relative_diff() const {
  return a != 0 ? (b - a) / std::abs(a) : std::numeric_limits<double>::quiet_NaN();
}

std::vector<ComparisonRow> compare_biomarkers(const RunRecord& a, const RunRecord& b) {
  std::vector<ComparisonRow> rows;
  for (const char* type : {"myocyte", "fibroblast"}) {
    if (!a.mean_biomarkers.contains(type) && !b.mean_biomarkers.contains(type)) continue;
    for (const char* metric : kMetrics)
      rows.push_back({type, metric, value_of(a.mean_biomarkers, type, metric),
                      value_of(b.mean_biomarkers, type, metric)});
    // The means are over the beats where the cells fired: how many did not, where any did not.
    const double not_fired_a = value_of(a.mean_biomarkers, type, "beats_not_fired"),
                 not_fired_b = value_of(b.mean_biomarkers, type, "beats_not_fired");
    if (not_fired_a > 0 || not_fired_b > 0) rows.push_back({type, "beats_not_fired", not_fired_a, not_fired_b});
  }
  return rows;
}

std::string comparison_markdown(const RunRecord& a, const RunRecord& b) {
  std::ostringstream md;
  md << "| cell type | biomarker | " << a.label << " | " << b.label << " | " << b.label << " - " << a.label
     << " | relative |\n|---|---|---:|---:|---:|---:|\n";
  for (const auto& r : compare_biomarkers(a, b))
    md << "| " << r.type << " | " << r.metric << " | " << fixed(r.a, 2) << " | " << fixed(r.b, 2) << " | "
       << fixed(r.diff(), 2) << " | " << fixed(100 * r.relative_diff(), 1) << " % |\n";
  return md.str();
}

namespace {

// traces.png: each shared column (the first six) in a panel, A and B overlaid.
void write_traces_plot(const RunRecord& a, const RunRecord& b, const std::filesystem::path& file) {
  const std::vector<PlotPanel> panels = comparison_trace_panels(a, b);
  const std::size_t columns = std::min<std::size_t>(3, panels.size()), rows = (panels.size() + columns - 1) / columns;
  write_plot_png(panels, file,
                 {.width_px = 520 * static_cast<int>(columns), .height_px = 30 + 360 * static_cast<int>(rows),
                  .font_px = 13, .title = a.label + " and " + b.label, .columns = columns});
}

}  // namespace

void write_comparison(const RunRecord& a, const RunRecord& b, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream md(dir / "comparison.md");
    md << "# " << a.label << " vs " << b.label << "\n\nPer-cell-type mean biomarkers.\n\n"
       << comparison_markdown(a, b);
  }
  CsvWriter csv(dir / "comparison.csv", {"type", "metric", "a", "b", "b_minus_a", "relative_diff"});
  for (const auto& r : compare_biomarkers(a, b)) {
    csv.cell(r.type).cell(r.metric).cell(r.a).cell(r.b).cell(r.diff()).cell(r.relative_diff());
    csv.end_row();
  }

  // Traces of the columns both runs have, on a common time base.
  const auto shared = shared_columns(a, b);
  std::vector<std::string> header = {"t_ms"};
  for (const auto& [i, j] : shared) {
    header.push_back(a.label + ":" + a.columns[i]);
    header.push_back(b.label + ":" + b.columns[j]);
  }
  CsvWriter traces(dir / "traces.csv", header);
  if (shared.empty() || a.times_ms.size() < 2 || b.times_ms.size() < 2) return;
  write_traces_plot(a, b, dir / "traces.png");
  const double t0 = std::max(a.times_ms.front(), b.times_ms.front());
  const double t1 = std::min(a.times_ms.back(), b.times_ms.back());
  const double h = std::min(finest_interval(a.times_ms), finest_interval(b.times_ms));
  for (long k = 0; t0 + static_cast<double>(k) * h <= t1 + 1e-9; ++k) {
    const double t = t0 + static_cast<double>(k) * h;
    traces.cell(t);
    for (const auto& [i, j] : shared) {
      traces.cell(interpolate(a.times_ms, a.samples[i], t));
      traces.cell(interpolate(b.times_ms, b.samples[j], t));
    }
    traces.end_row();
  }
}

}  // namespace fibrodem
