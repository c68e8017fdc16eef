// Draws plot panels (io/plot_png.hpp) onto any Cairo surface: an image for
// PNG files (plot_png.cpp), an SVG stream for reports (plot_svg.cpp), so both
// show the same plot from one drawing code.
#pragma once

#include <cairo.h>

#include <vector>

#include "io/plot_png.hpp"

namespace fibrodem::cairo {

// Paints the whole options.width_px x options.height_px area white, then the
// title and the panels.
void draw_plot(cairo_t* c, const std::vector<PlotPanel>& panels, const PlotOptions& options);

}  // namespace fibrodem::cairo
