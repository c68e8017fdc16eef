#include "report/trace_panels.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace fibrodem {

TraceHeading parse_trace_heading(const std::string& name) {
  const std::size_t underscore = name.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == name.size()) return {name, -1};
  const std::string tail = name.substr(underscore + 1);
  if (!std::all_of(tail.begin(), tail.end(), [](unsigned char c) { return std::isdigit(c); })) return {name, -1};
  return {name.substr(0, underscore), std::stoi(tail)};
}

void thin_min_max(const std::vector<double>& t, const std::vector<double>& y, std::size_t most_points,
                  std::vector<double>& t_out, std::vector<double>& y_out) {
  const std::size_t n = std::min(t.size(), y.size());
  if (n <= most_points || most_points < 2) {
    t_out.assign(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(n));
    y_out.assign(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(n));
    return;
  }
  const std::size_t buckets = most_points / 2;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t begin = b * n / buckets, end = (b + 1) * n / buckets;
    std::size_t lo = begin, hi = begin;
    for (std::size_t i = begin; i < end; ++i) {
      if (y[i] < y[lo] || std::isnan(y[lo])) lo = i;
      if (y[i] > y[hi] || std::isnan(y[hi])) hi = i;
    }
    // In time order, so the line goes through both.
    for (std::size_t i : {std::min(lo, hi), std::max(lo, hi)}) {
      t_out.push_back(t[i]);
      y_out.push_back(y[i]);
      if (lo == hi) break;
    }
  }
}

std::vector<PlotPanel> trace_panels(const CsvTable& traces, const std::map<int, std::string>& types,
                                    const std::map<std::string, std::string>& units) {
  const auto time_column = traces.column("t_ms");
  if (!time_column || traces.rows.empty()) return {};
  const std::vector<double> t = traces.numbers(*time_column);
  std::vector<PlotPanel> panels;
  std::map<std::string, std::size_t> panel_of;
  std::map<std::string, std::size_t> left_out;
  for (std::size_t c = 0; c < traces.header.size(); ++c) {
    if (c == *time_column) continue;
    const TraceHeading column = parse_trace_heading(traces.header[c]);
    if (!panel_of.count(column.variable)) {
      panel_of[column.variable] = panels.size();
      const auto unit = units.find(column.variable);
      const bool has_unit = unit != units.end() && !unit->second.empty();
      panels.push_back({column.variable, "t [ms]", column.variable + (has_unit ? " [" + unit->second + "]" : ""),
                        false, false, {}, {}});
    }
    PlotPanel& panel = panels[panel_of[column.variable]];
    if (panel.series.size() == kMostSeriesPerPanel) {
      ++left_out[column.variable];
      continue;
    }
    std::string label = column.cell < 0 ? column.variable : "cell " + std::to_string(column.cell);
    if (const auto type = types.find(column.cell); type != types.end()) label += " (" + type->second + ")";
    PlotSeries series{label, {}, {}};
    series.markers = false;
    thin_min_max(t, traces.numbers(c), kMostPoints, series.x, series.y);
    panel.series.push_back(std::move(series));
  }
  for (const auto& [variable, count] : left_out)
    panels[panel_of[variable]].title += " (first " + std::to_string(kMostSeriesPerPanel) + " cells; " +
                                        std::to_string(count) + " more in traces.csv)";
  return panels;
}

}  // namespace fibrodem
