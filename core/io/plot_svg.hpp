// The plots of io/plot_png as SVG text, for inline use in an HTML report: the
// same drawing (modules/drawing/plot_draw.hpp) on Cairo's SVG surface, written to memory.
#pragma once

#include <string>
#include <vector>

#include "io/plot_png.hpp"

namespace fibrodem {

// An <svg> element that scales to its container's width (its viewBox is
// options.width_px x options.height_px). Cairo names the glyphs and clip
// paths it defines (id="glyph0-1", ...); several SVGs in one HTML document
// share one id space, so every id and reference is prefixed with
// `id_prefix` (which must be unique in the document). Throws
// std::runtime_error if Cairo fails.
std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options, const std::string& id_prefix);

}  // namespace fibrodem
