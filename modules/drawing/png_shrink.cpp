#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include "cairo_drawing.hpp"
#include "png_file.hpp"

namespace fibrodem::cairo {

namespace {

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return in ? bytes.str() : std::string();
}

}  // namespace

std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px) {
  Surface image(cairo_image_surface_create_from_png(png.c_str()), cairo_surface_destroy);
  if (cairo_surface_status(image.get()) != CAIRO_STATUS_SUCCESS) return {};
  const int width = cairo_image_surface_get_width(image.get()), height = cairo_image_surface_get_height(image.get());
  if (width <= max_width_px) return file_bytes(png);
  const double scale = static_cast<double>(max_width_px) / width;
  const int small_height = std::max(1, static_cast<int>(std::lround(height * scale)));
  Surface small(cairo_image_surface_create(CAIRO_FORMAT_RGB24, max_width_px, small_height), cairo_surface_destroy);
  cairo_t* cr = cairo_create(small.get());
  cairo_scale(cr, scale, scale);
  cairo_set_source_surface(cr, image.get(), 0, 0);
  // Nearest pixel: no blended colours, so every colour is still one of the
  // colour bar's and a snapshot keeps its palette (a small PNG).
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_destroy(cr);
  try {
    return png_bytes(small.get());
  } catch (const std::exception&) {
    return {};
  }
}

}  // namespace fibrodem::cairo
