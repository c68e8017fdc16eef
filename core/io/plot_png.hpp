// A small line-plot writer on Cairo for work-precision diagrams and the like:
// one or more panels side by side, each with log (decade ticks, labels 10^k,
// minor ticks at 2..9) or linear axes, axis labels, a title, series drawn as
// lines with markers (one colour and marker shape per series) and a legend,
// optional error bars, and optional dashed horizontal guide lines (e.g. error
// thresholds).
// Points that cannot be drawn (non-finite, or <= 0 on a log axis) are left
// out, and a series' line is broken there. Drawn by the drawing module,
// opened on the first plot (io/drawing.hpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace fibrodem {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  // Error bars (e.g. a 95 % confidence interval): from y_low to y_high at
  // each x, where both are given and finite; empty: none.
  std::vector<double> y_low = {}, y_high = {};
  // A marker at every point; off for dense samples (traces, histograms).
  bool markers = true;
};

struct PlotGuide {
  double y = 0;
  std::string label;  // drawn at the right end of the line
};

struct PlotPanel {
  std::string title, x_label, y_label;
  bool log_x = true, log_y = true;
  std::vector<PlotSeries> series;
  std::vector<PlotGuide> guides;
};

struct PlotOptions {
  int width_px = 1200, height_px = 600;  // the whole image
  double font_px = 15;
  std::string title;  // above all panels
  std::size_t columns = 0;  // panels per row (0: all in one row)
};

// Throws std::runtime_error if the file cannot be written.
void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                    const PlotOptions& options = {});

}  // namespace fibrodem
