#include <cairo.h>

#include <memory>
#include <stdexcept>

#include "cairo_drawing.hpp"
#include "plot_draw.hpp"
#include "png_file.hpp"

namespace fibrodem::cairo {

void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                    const PlotOptions& options) {
  if (options.width_px <= 0 || options.height_px <= 0) throw std::runtime_error("plot: image size must be positive");
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, options.width_px, options.height_px), cairo_surface_destroy);
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), cairo_destroy);
  draw_plot(cr.get(), panels, options);
  std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
  write_png_file(surface.get(), file);
}

}  // namespace fibrodem::cairo
