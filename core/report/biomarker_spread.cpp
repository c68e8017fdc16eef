#include "report/biomarker_spread.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "measure/sample_statistics.hpp"

namespace fibrodem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The types in order of first appearance.
std::vector<std::string> types_of(const CsvTable& table, std::size_t type_column) {
  std::vector<std::string> types;
  for (const auto& row : table.rows)
    if (std::find(types.begin(), types.end(), row[type_column]) == types.end()) types.push_back(row[type_column]);
  return types;
}

std::vector<double> finite_values_of(const CsvTable& table, std::size_t type_column, const std::string& type,
                                     std::size_t column) {
  std::vector<double> values;
  const std::vector<double> all = table.numbers(column);
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    if (table.rows[r][type_column] == type && std::isfinite(all[r])) values.push_back(all[r]);
  return values;
}

}  // namespace

std::vector<BiomarkerSpread> biomarker_spread(const CsvTable& biomarkers) {
  std::vector<BiomarkerSpread> out;
  const auto type_column = biomarkers.column("type");
  if (!type_column) return out;
  for (const auto& type : types_of(biomarkers, *type_column))
    for (const auto& metric : kBiomarkerColumns) {
      const auto column = biomarkers.column(metric);
      if (!column) continue;
      const std::vector<double> values = finite_values_of(biomarkers, *type_column, type, *column);
      const SampleSummary s = summarize(values);
      BiomarkerSpread spread{type, metric, values.size(), s.mean, s.sd, kNaN, kNaN};
      if (!values.empty()) {
        const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
        spread.min = *lo;
        spread.max = *hi;
      }
      out.push_back(spread);
    }
  return out;
}

std::vector<PlotPanel> biomarker_histograms(const CsvTable& biomarkers) {
  std::vector<PlotPanel> panels;
  const auto type_column = biomarkers.column("type");
  if (!type_column) return panels;
  for (const auto& type : types_of(biomarkers, *type_column))
    for (const auto& metric : kBiomarkerColumns) {
      const auto column = biomarkers.column(metric);
      if (!column) continue;
      const std::vector<double> values = finite_values_of(biomarkers, *type_column, type, *column);
      if (values.empty()) continue;
      const auto [lo_it, hi_it] = std::minmax_element(values.begin(), values.end());
      double lo = *lo_it, hi = *hi_it;
      if (hi - lo < 1e-9 * std::max(1.0, std::abs(lo))) lo -= 0.5, hi += 0.5;  // one value: one bin around it
      const std::size_t bins = static_cast<std::size_t>(std::ceil(std::log2(static_cast<double>(values.size())))) + 1;
      const double width = (hi - lo) / static_cast<double>(bins);
      std::vector<double> count(bins, 0.0);
      for (double v : values) ++count[std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, (v - lo) / width)))];
      // A step line: up and across each bar.
      PlotSeries series{"n = " + std::to_string(values.size()), {lo}, {0.0}};
      series.markers = false;
      for (std::size_t b = 0; b < bins; ++b) {
        const double left = lo + static_cast<double>(b) * width;
        series.x.insert(series.x.end(), {left, left + width});
        series.y.insert(series.y.end(), {count[b], count[b]});
      }
      series.x.push_back(hi);
      series.y.push_back(0.0);
      panels.push_back({type + ": " + metric, metric, "cell-beats", false, false, {std::move(series)}, {}});
    }
  return panels;
}

std::map<int, std::string> cell_types(const CsvTable& biomarkers) {
  std::map<int, std::string> types;
  const auto cell = biomarkers.column("cell"), type = biomarkers.column("type");
  if (!cell || !type) return types;
  for (const auto& row : biomarkers.rows) {
    char* end = nullptr;
    const long index = std::strtol(row[*cell].c_str(), &end, 10);
    if (end != row[*cell].c_str()) types.emplace(static_cast<int>(index), row[*type]);
  }
  return types;
}

}  // namespace fibrodem
