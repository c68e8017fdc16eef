// Draws plot panels (io/plot_png.hpp) onto any Cairo surface: an image for
// PNG files (io/plot_png), an SVG stream for reports (io/plot_svg), so both
// show the same plot from one drawing code.
#pragma once

#include <vector>

#include "io/plot_png.hpp"

struct _cairo;  // cairo_t, without Cairo's header

namespace fibrodem {

// Paints the whole options.width_px x options.height_px area white, then the
// title and the panels.
void draw_plot(_cairo* c, const std::vector<PlotPanel>& panels, const PlotOptions& options);

}  // namespace fibrodem
