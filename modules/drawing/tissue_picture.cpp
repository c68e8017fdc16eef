#include "cairo_drawing.hpp"
#include "io/picture_frame.hpp"
#include "io/tissue_imprint.hpp"
#include "png_file.hpp"
#include "util/number_text.hpp"

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

namespace fibrodem::cairo {
namespace {

struct Rgb {
  double r, g, b;
};

// Viridis, sampled at 9 points and interpolated linearly.
Rgb colour_map(double t) {
  static constexpr std::array<Rgb, 9> stops = {{{0.267, 0.005, 0.329},
                                                {0.279, 0.175, 0.483},
                                                {0.230, 0.322, 0.546},
                                                {0.173, 0.449, 0.558},
                                                {0.128, 0.567, 0.551},
                                                {0.153, 0.683, 0.502},
                                                {0.361, 0.786, 0.388},
                                                {0.668, 0.862, 0.196},
                                                {0.993, 0.906, 0.144}}};
  if (!std::isfinite(t)) return {0.6, 0.6, 0.6};
  t = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(t), stops.size() - 2);
  const double f = t - i;
  const Rgb a = stops[i], b = stops[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

Rgb type_colour(CellType t) {
  return t == CellType::myocyte ? Rgb{0.20, 0.40, 0.85} : Rgb{0.15, 0.70, 0.25};
}

// The colour bar's height in pixels, a colour each.
constexpr int kColourBarSteps = 200;

// t in [0, 1] moved to the middle of its colour-bar step (its row's colour).
double colour_bar_step(double t) {
  if (!std::isfinite(t)) return t;
  const int step = std::min(kColourBarSteps - 1, static_cast<int>(std::clamp(t, 0.0, 1.0) * kColourBarSteps));
  return (step + 0.5) / kColourBarSteps;
}

// Cairo's RGB24 pixel, 0x00RRGGBB.
std::uint32_t rgb24(const Rgb& col) {
  const auto byte = [](double v) { return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  return byte(col.r) << 16 | byte(col.g) << 8 | byte(col.b);
}

// Sets the pixels of an RGB24 image whose centres lie within radius r of (cx, cy).
void fill_disk(unsigned char* data, int stride, int width, int height, double cx, double cy, double r,
               std::uint32_t pixel) {
  for_each_disk_span(width, height, cx, cy, r, [&](int y, int x0, int x1) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    std::fill(row + x0, row + x1 + 1, pixel);
  });
}

// A released tissue's picture, from its imprint's pixels: the frame must be
// the one the imprint was made in (the picture may be narrower: no colour bar).
void fill_from_raster(unsigned char* data, int stride, const PictureFrame& f, const CellRaster& raster,
                      const auto& pixel_of_cell) {
  const PictureFrame& r = raster.frame;
  if (r.bounds_um != f.bounds_um || r.px_per_um != f.px_per_um || r.margin_px != f.margin_px ||
      r.top_px != f.top_px || f.width_px > r.width_px || f.height_px > r.height_px)
    throw std::logic_error("write_tissue_png: the tissue's particles were released; its imprint holds the picture "
                           "with a title at the default scale only");
  for (int y = 0; y < f.height_px; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    for (int x = 0; x < f.width_px; ++x)
      if (const std::int32_t cell = raster.at(x, y); cell >= 0) row[x] = pixel_of_cell(cell);
  }
}

// The paths over the cells: a black halo under each line, so that it shows
// on any colour of the map, then the line and a dot at its last point.
void draw_paths(cairo_t* c, const std::vector<PicturePath>& paths, const auto& px, const auto& py) {
  cairo_set_line_join(c, CAIRO_LINE_JOIN_ROUND);
  for (const bool halo : {true, false})
    for (const auto& path : paths) {
      if (path.x_um.empty() || path.x_um.size() != path.y_um.size()) continue;
      if (halo) cairo_set_source_rgb(c, 0, 0, 0);
      else if (path.light) cairo_set_source_rgb(c, 1, 1, 1);
      else cairo_set_source_rgb(c, 0.9, 0.1, 0.1);
      cairo_set_line_width(c, halo ? 4 : 2);
      cairo_move_to(c, px(path.x_um[0]), py(path.y_um[0]));
      for (std::size_t k = 1; k < path.x_um.size(); ++k) cairo_line_to(c, px(path.x_um[k]), py(path.y_um[k]));
      cairo_stroke(c);
      cairo_arc(c, px(path.x_um.back()), py(path.y_um.back()), halo ? 5 : 3.5, 0, 2 * M_PI);
      cairo_fill(c);
    }
}

}  // namespace

void write_tissue_png(const Tissue& tissue, const std::array<double, 4>& bounds_um,
                      const std::filesystem::path& file, const std::vector<double>* values,
                      const PictureOptions& options) {
  const PictureFrame f = picture_frame(bounds_um, options, values != nullptr);
  const double scale = f.px_per_um;
  const int margin = f.margin_px, font = f.font_px, top = f.top_px;
  const int tissue_w = f.tissue_width_px, width = f.width_px, height = f.height_px;
  const TissueImprint* imprint = tissue.particles.empty() ? tissue.imprint() : nullptr;
  if (imprint && options.draw_bonds)
    throw std::logic_error("write_tissue_png: the tissue's particles and bonds were released: no bonds to draw");

  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height), cairo_surface_destroy);
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), cairo_destroy);
  cairo_t* c = cr.get();
  cairo_set_source_rgb(c, 1, 1, 1);
  cairo_paint(c);

  // Tissue coordinates to pixels (y up).
  auto px = [&](double x) { return f.x_px(x); };
  auto py = [&](double y) { return f.y_px(y); };

  double lo = 0, hi = 1;
  if (values) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (double v : *values)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (options.value_min) lo = *options.value_min;
    if (options.value_max) hi = *options.value_max;
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
    if (hi <= lo) hi = lo + 1;
  }
  if (options.antialias && !imprint) {
    // Disks of a few pixels: a coarser arc tolerance (0.25 px) is invisible.
    cairo_set_tolerance(c, 0.25);
    // Consecutive particles of one colour (a myocyte's seven) are filled as one
    // path: one rasterisation instead of seven.
    for (std::size_t i = 0; i < tissue.particles.size();) {
      const int cell = tissue.particles[i].cell;
      const Rgb col = values ? colour_map(((*values)[cell] - lo) / (hi - lo)) : type_colour(tissue.type[cell]);
      cairo_set_source_rgb(c, col.r, col.g, col.b);
      for (; i < tissue.particles.size() && tissue.particles[i].cell == cell; ++i) {
        const Particle& p = tissue.particles[i];
        cairo_new_sub_path(c);
        cairo_arc(c, px(p.x_um), py(p.y_um), f.radius_px(p.r_um), 0, 2 * M_PI);
      }
      cairo_fill(c);
    }
  } else {
    // Each pixel one colour: the pixels whose centres fall in a disk, span by
    // span, as Cairo's unantialiased fill would choose them. (Cairo's general
    // path fill costs ~0.6 us per disk of ~2 px here, the spans ~0.05 us: a
    // snapshot of the Fig. 3 tissue has 16 653 particles.)
    cairo_surface_flush(surface.get());
    auto* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    // The colour bar's colours only (steps of 1/200 of the range), and text
    // and lines without grey edges: the picture then fits a PNG palette.
    const auto pixel_of_cell = [&](int cell) {
      return rgb24(values ? colour_map(colour_bar_step(((*values)[cell] - lo) / (hi - lo)))
                          : type_colour(tissue.type[cell]));
    };
    if (imprint) fill_from_raster(data, stride, f, imprint->picture, pixel_of_cell);
    for (const Particle& p : tissue.particles)
      fill_disk(data, stride, width, height, px(p.x_um), py(p.y_um), f.radius_px(p.r_um), pixel_of_cell(p.cell));
    cairo_surface_mark_dirty(surface.get());
    cairo_set_antialias(c, CAIRO_ANTIALIAS_NONE);
    std::unique_ptr<cairo_font_options_t, decltype(&cairo_font_options_destroy)> sharp(
        cairo_font_options_create(), cairo_font_options_destroy);
    cairo_font_options_set_antialias(sharp.get(), CAIRO_ANTIALIAS_NONE);
    cairo_set_font_options(c, sharp.get());
  }
  if (options.draw_bonds) {
    cairo_set_source_rgb(c, 0.9, 0.1, 0.1);
    cairo_set_line_width(c, std::max(0.5, 0.6 * scale));
    for (const Bond& bd : tissue.bonds) {
      const Particle &p = tissue.particles[bd.p], &q = tissue.particles[bd.q];
      cairo_move_to(c, px(p.x_um), py(p.y_um));
      cairo_line_to(c, px(q.x_um), py(q.y_um));
    }
    cairo_stroke(c);
  }
  draw_paths(c, options.paths, px, py);

  cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(c, font);
  cairo_set_source_rgb(c, 0, 0, 0);
  if (!options.title.empty()) {
    cairo_move_to(c, margin, margin + font);
    cairo_show_text(c, options.title.c_str());
  }
  // Scale bar: 1 mm (or 100 um if the tissue is narrower than 1 mm).
  const double bar_um = tissue_w / scale >= 1000 ? 1000 : 100;
  const double sy = height - margin / 2.0;
  cairo_set_line_width(c, 2);
  cairo_move_to(c, margin, sy);
  cairo_line_to(c, margin + bar_um * scale, sy);
  cairo_stroke(c);
  cairo_set_font_size(c, 10);
  cairo_move_to(c, margin + bar_um * scale + 4, sy + 4);
  cairo_show_text(c, bar_um >= 1000 ? "1 mm" : "100 um");

  if (values) {  // colour bar with its range
    const double x0 = margin + tissue_w + 30, w = 20, y0 = top + 20, h = kColourBarSteps;
    for (int i = 0; i < static_cast<int>(h); ++i) {
      const Rgb col = colour_map(1.0 - (i + 0.5) / h);
      cairo_set_source_rgb(c, col.r, col.g, col.b);
      cairo_rectangle(c, x0, y0 + i, w, 1);
      cairo_fill(c);
    }
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_set_line_width(c, 1);
    cairo_rectangle(c, x0, y0, w, h);
    cairo_stroke(c);
    cairo_set_font_size(c, 12);
    cairo_move_to(c, x0 + w + 4, y0 + 5);
    cairo_show_text(c, significant_digits(hi, 4).c_str());
    cairo_move_to(c, x0 + w + 4, y0 + h + 5);
    cairo_show_text(c, significant_digits(lo, 4).c_str());
    if (!options.value_label.empty()) {
      cairo_move_to(c, x0 - 10, y0 - 8);
      cairo_show_text(c, options.value_label.c_str());
    }
  }
  write_png_file(surface.get(), file);
}

}  // namespace fibrodem::cairo
