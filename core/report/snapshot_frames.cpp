#include "report/snapshot_frames.hpp"

#include <cairo.h>

#include <cmath>
#include <memory>

#include "io/png_file.hpp"
#include "report/html_document.hpp"

namespace fibrodem {

std::vector<std::size_t> evenly_spread(std::size_t n, std::size_t most) {
  std::vector<std::size_t> picked;
  if (n == 0 || most == 0) return picked;
  if (n <= most || most == 1) {
    for (std::size_t k = 0; k < std::min(n, most); ++k) picked.push_back(k);
    return picked;
  }
  // k (n - 1) / (most - 1), rounded: distinct since the step exceeds 1.
  for (std::size_t k = 0; k < most; ++k)
    picked.push_back(static_cast<std::size_t>(std::llround(static_cast<double>(k) * (n - 1) / (most - 1))));
  return picked;
}

namespace {
using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
}  // namespace

std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px) {
  Surface image(cairo_image_surface_create_from_png(png.c_str()), cairo_surface_destroy);
  if (cairo_surface_status(image.get()) != CAIRO_STATUS_SUCCESS) return {};
  const int width = cairo_image_surface_get_width(image.get()), height = cairo_image_surface_get_height(image.get());
  if (width <= max_width_px) return read_file_bytes(png).value_or(std::string());
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

std::vector<std::pair<std::string, std::string>> animation_frames(
    const std::vector<std::pair<std::string, std::filesystem::path>>& frames, std::size_t most, int max_width_px) {
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t k : evenly_spread(frames.size(), most)) {
    std::string bytes = png_at_most_wide(frames[k].second, max_width_px);
    if (!bytes.empty()) out.emplace_back(frames[k].first, std::move(bytes));
  }
  return out;
}

}  // namespace fibrodem
