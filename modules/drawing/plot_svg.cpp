#include <cairo-svg.h>
#include <cairo.h>

#include <memory>
#include <stdexcept>

#include "cairo_drawing.hpp"
#include "plot_draw.hpp"

namespace fibrodem::cairo {

namespace {

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

// Cairo's ids (id="..."), and references to them (href="#...", url(#...)),
// made unique in the HTML document.
void prefix_ids(std::string& svg, const std::string& prefix) {
  replace_all(svg, "id=\"", "id=\"" + prefix);
  replace_all(svg, "href=\"#", "href=\"#" + prefix);
  replace_all(svg, "url(#", "url(#" + prefix);
}

// The root element: Cairo writes a fixed size in points; a report wants it
// as wide as the page, its height following the viewBox's aspect.
std::string scalable_root(std::string svg, const PlotOptions& options) {
  const std::size_t open = svg.find("<svg");
  if (open == std::string::npos) throw std::runtime_error("plot: Cairo wrote no <svg> element");
  const std::size_t close = svg.find('>', open);
  const std::string root = "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
                           "viewBox=\"0 0 " + std::to_string(options.width_px) + " " +
                           std::to_string(options.height_px) + "\" style=\"width:100%;height:auto\" role=\"img\">";
  return root + svg.substr(close + 1);
}

}  // namespace

std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options, const std::string& id_prefix) {
  if (options.width_px <= 0 || options.height_px <= 0) throw std::runtime_error("plot: image size must be positive");
  std::string svg;
  {
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
        cairo_svg_surface_create_for_stream(append_to_string, &svg, options.width_px, options.height_px),
        cairo_surface_destroy);
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), cairo_destroy);
    draw_plot(cr.get(), panels, options);
    cairo_surface_finish(surface.get());  // writes the document's end
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
      throw std::runtime_error(std::string("plot: Cairo SVG: ") + cairo_status_to_string(cairo_surface_status(surface.get())));
  }
  // Everything before the root element (the XML declaration) is not for HTML.
  const std::size_t open = svg.find("<svg");
  if (open != std::string::npos) svg.erase(0, open);
  prefix_ids(svg, id_prefix);
  return scalable_root(std::move(svg), options);
}

}  // namespace fibrodem::cairo
