// traces.csv as plot panels: one panel per traced variable (V, Ca_i,
// sarcomere_length, eps_xx, ...), the traced cells overlaid and labelled with
// their index and, where known, their cell type.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "io/plot_png.hpp"

namespace fibrodem {

// A traces.csv heading VAR_CELL split into the variable and the cell (-1: a
// tissue-wide column such as eps_xx or dt_ms).
struct TraceHeading {
  std::string variable;
  int cell = -1;
};
TraceHeading parse_trace_heading(const std::string& name);

// Most series a panel overlays (one colour each); the rest are left out and
// the panel's title says how many.
inline constexpr std::size_t kMostSeriesPerPanel = 10;
// Samples above this many per series are thinned to the minimum and maximum
// of each of kMostPoints / 2 time buckets, so upstrokes and peaks stay while
// the page stays small.
inline constexpr std::size_t kMostPoints = 3000;

// `types`: cell index -> type name, for the legend (cells not in it are
// labelled by index alone). `units`: variable -> unit (summary.json
// "trace_units"), for the y axis ("V [mV]"); a variable not in it is
// labelled by its name alone.
std::vector<PlotPanel> trace_panels(const CsvTable& traces, const std::map<int, std::string>& types,
                                    const std::map<std::string, std::string>& units = {});

// The min-max thinning described above (exposed for its test).
void thin_min_max(const std::vector<double>& t, const std::vector<double>& y, std::size_t most_points,
                  std::vector<double>& t_out, std::vector<double>& y_out);

}  // namespace fibrodem
