// What the drawing module (libfibrodem-drawing.so) does on Cairo, behind the
// core's io/drawing.hpp interface: the core's public functions of the same
// names (io/plot_png.hpp, io/plot_svg.hpp, io/tissue_picture.hpp,
// report/snapshot_frames.hpp) check their arguments and forward here.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "io/plot_png.hpp"
#include "io/tissue_picture.hpp"

namespace fibrodem::cairo {

void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                    const PlotOptions& options);

std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options, const std::string& id_prefix);

// bounds_um: the tissue's x_min, x_max, y_min, y_max (Tissue::bounds_um(),
// computed by the caller: the module uses no code of the core).
void write_tissue_png(const Tissue& tissue, const std::array<double, 4>& bounds_um,
                      const std::filesystem::path& file, const std::vector<double>* cell_values,
                      const PictureOptions& options);

std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px);

}  // namespace fibrodem::cairo
