// Where a tissue picture (io/tissue_picture.hpp) puts things: its size, the
// tissue's place and scale in it, and which pixels a particle's disk covers
// when drawn without antialiasing. Shared by the drawing module, which draws
// the picture, and the core, which keeps a released tissue's particles as
// pixels (io/tissue_imprint.hpp): both then choose the same pixels.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "io/tissue_picture.hpp"

namespace fibrodem {

struct PictureFrame {
  std::array<double, 4> bounds_um{};  // x_min, x_max, y_min, y_max (widened by 1 um where empty)
  double px_per_um = 0;
  int margin_px = 20, font_px = 14;
  int top_px = 0;  // where the tissue's top edge lies
  int tissue_width_px = 0, tissue_height_px = 0, colour_bar_width_px = 0;
  int width_px = 0, height_px = 0;  // the whole picture's

  // Tissue coordinates to pixels (y up).
  double x_px(double x_um) const { return margin_px + (x_um - bounds_um[0]) * px_per_um; }
  double y_px(double y_um) const { return top_px + (bounds_um[3] - y_um) * px_per_um; }
  // The radius a particle is drawn with: half a pixel at least.
  double radius_px(double r_um) const { return std::max(0.5, r_um * px_per_um); }
};

// The frame of a picture of a tissue with these bounds (Tissue::bounds_um())
// drawn with `options`, with a colour bar if it shows values. Throws
// std::runtime_error if the picture would be too large for a PNG.
inline PictureFrame picture_frame(std::array<double, 4> b, const PictureOptions& options, bool with_values) {
  if (!(b[1] > b[0])) b[0] -= 1, b[1] += 1;
  if (!(b[3] > b[2])) b[2] -= 1, b[3] += 1;
  PictureFrame f;
  f.bounds_um = b;
  f.px_per_um = options.pixels_per_um > 0 ? options.pixels_per_um : std::max(1, options.height_px) / (b[3] - b[2]);
  f.top_px = f.margin_px + (options.title.empty() ? 0 : f.font_px + 8);
  f.tissue_width_px = static_cast<int>(std::ceil((b[1] - b[0]) * f.px_per_um));
  f.tissue_height_px = static_cast<int>(std::ceil((b[3] - b[2]) * f.px_per_um));
  f.colour_bar_width_px = with_values ? 110 : 0;
  f.width_px = f.margin_px + f.tissue_width_px + f.colour_bar_width_px + f.margin_px;
  f.height_px = f.top_px + std::max(f.tissue_height_px, with_values ? 240 : 0) + f.margin_px;
  if (f.width_px > 32767 || f.height_px > 32767)
    throw std::runtime_error("write_tissue_png: image too large; lower height_px or pixels_per_um");
  return f;
}

// The pixels of a width x height image whose centres lie within radius r of
// (cx, cy), as spans: span(row, first column, last column), row by row.
// (What Cairo's unantialiased fill of the disk would choose.)
template <class Span>
void for_each_disk_span(int width, int height, double cx, double cy, double r, Span&& span) {
  const int y0 = std::max(0, static_cast<int>(std::ceil(cy - r - 0.5)));
  const int y1 = std::min(height - 1, static_cast<int>(std::floor(cy + r - 0.5)));
  for (int y = y0; y <= y1; ++y) {
    const double dy = y + 0.5 - cy, half = std::sqrt(std::max(0.0, r * r - dy * dy));
    const int x0 = std::max(0, static_cast<int>(std::ceil(cx - half - 0.5)));
    const int x1 = std::min(width - 1, static_cast<int>(std::floor(cx + half - 0.5)));
    if (x1 >= x0) span(y, x0, x1);
  }
}

}  // namespace fibrodem
