// `fibrodem plot SPEC.json --out FILE.png`: line plots from a JSON description,
// drawn by the same Cairo plotter as the sweeps and benchmarks (io/plot_png.hpp), so
// scripts (scripts/paper_report.py) get plots without a Python plotting package.
//   {"title": "...", "columns": 2, "width_px": 1200, "height_px": 800,
//    "panels": [{"title", "x_label", "y_label", "log_x": false, "log_y": false,
//                "series": [{"label", "x": [...], "y": [...],
//                            "y_low": [...], "y_high": [...]}]}]}
// A null in x, y, y_low or y_high is a point not drawn (NaN).
#include <fstream>
#include <limits>

#include "apps/commands.hpp"
#include "io/plot_png.hpp"
#include "util/json_reader.hpp"

namespace fibrodem::cli {

namespace {

std::vector<double> numbers(const json& parent, const char* key, const std::string& where) {
  std::vector<double> out;
  if (!parent.contains(key)) return out;
  const json& list = parent.at(key);
  if (!list.is_array()) throw ManifestError(where + "." + key, "expected a list of numbers");
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (list[i].is_null()) {
      out.push_back(std::numeric_limits<double>::quiet_NaN());
    } else if (list[i].is_number()) {
      out.push_back(list[i].get<double>());
    } else {
      throw ManifestError(where + "." + key + "[" + std::to_string(i) + "]",
                          "expected a number or null, got " + list[i].dump());
    }
  }
  return out;
}

PlotSeries read_series(const json& s, const std::string& where) {
  PlotSeries series{s.value("label", ""), numbers(s, "x", where), numbers(s, "y", where)};
  if (series.x.size() != series.y.size())
    throw ManifestError(where, "x has " + std::to_string(series.x.size()) + " values, y " +
                        std::to_string(series.y.size()) + " (expected as many)");
  series.y_low = numbers(s, "y_low", where);
  series.y_high = numbers(s, "y_high", where);
  if (series.y_low.size() != series.y_high.size() || (!series.y_low.empty() && series.y_low.size() != series.x.size()))
    throw ManifestError(where, "y_low and y_high need as many values as x (or neither)");
  return series;
}

}  // namespace

int plot_command(const std::string& spec_file, const std::string& out) {
  return guarded([&] {
    std::ifstream in(spec_file);
    if (!in) throw ManifestError(spec_file, "cannot be read");
    const json spec = json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (!spec.is_object() || !spec.contains("panels") || !spec["panels"].is_array() || spec["panels"].empty())
      throw ManifestError(spec_file, "expected a JSON object with a non-empty list \"panels\"");
    std::vector<PlotPanel> panels;
    for (std::size_t p = 0; p < spec["panels"].size(); ++p) {
      const json& pj = spec["panels"][p];
      const std::string where = spec_file + ": panels[" + std::to_string(p) + "]";
      PlotPanel panel{pj.value("title", ""), pj.value("x_label", ""), pj.value("y_label", ""),
                      pj.value("log_x", false), pj.value("log_y", false), {}, {}};
      if (pj.contains("series")) {
        for (std::size_t s = 0; s < pj["series"].size(); ++s)
          panel.series.push_back(read_series(pj["series"][s], where + ".series[" + std::to_string(s) + "]"));
      }
      panels.push_back(std::move(panel));
    }
    PlotOptions options;
    options.title = spec.value("title", "");
    options.columns = spec.value("columns", std::size_t{0});
    options.width_px = spec.value("width_px", options.width_px);
    options.height_px = spec.value("height_px", options.height_px);
    write_plot_png(panels, out, options);
    return 0;
  });
}

}  // namespace fibrodem::cli
