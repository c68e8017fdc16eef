// PNG pictures of a tissue (Cairo): every particle a disk, coloured by its
// cell's type (as the seed paper's Fig. 2: myocytes blue, fibroblasts green)
// or, given one value per cell (e.g. membrane potential), by a colour map
// with a colour bar showing its range.
// Drawn by the drawing module, opened on the first picture (io/drawing.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

// A line drawn over the cells through points in the tissue's plane (a
// phase singularity's tip path), with a dot at its last point.
struct PicturePath {
  std::vector<double> x_um, y_um;
  bool light = true;  // white, or red (two kinds told apart), each on a black halo
};

struct PictureOptions {
  int height_px = 1500;            // image height of the tissue (6 mm -> 0.24 px/um)
  double pixels_per_um = 0;        // > 0: fixed scale instead of height_px
  std::string value_label;         // colour-bar title, e.g. "V (mV)"
  std::optional<double> value_min, value_max;  // colour-map range (default: the values' range)
  bool draw_bonds = false;         // red lines between bonded particles (Fig. 2 style)
  std::string title;               // text above the tissue, e.g. "t = 104.7 ms"
  // Smooth disk edges (Cairo). Off, a disk is the pixels whose centres it
  // covers, filled directly: drawing and compressing a 3000-cell tissue then
  // costs a fraction (snapshots).
  bool antialias = true;
  std::vector<PicturePath> paths;  // drawn over the cells
};

// Throws std::runtime_error if the file cannot be written or `cell_values`
// does not hold one value per cell.
void write_tissue_png(const Tissue& tissue, const std::filesystem::path& file,
                      const std::vector<double>* cell_values = nullptr,
                      const PictureOptions& options = {});

}  // namespace fibrodem
