// The drawing module's entry point: the core's Drawing interface
// (io/drawing.hpp) over this module's Cairo code.
#include "cairo_drawing.hpp"
#include "io/drawing.hpp"

namespace fibrodem::cairo {
namespace {

class CairoDrawing final : public Drawing {
 public:
  void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                      const PlotOptions& options) const override {
    cairo::write_plot_png(panels, file, options);
  }
  std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options,
                       const std::string& id_prefix) const override {
    return cairo::plot_svg(panels, options, id_prefix);
  }
  void write_tissue_png(const Tissue& tissue, const std::array<double, 4>& bounds_um,
                        const std::filesystem::path& file, const std::vector<double>* cell_values,
                        const PictureOptions& options) const override {
    cairo::write_tissue_png(tissue, bounds_um, file, cell_values, options);
  }
  std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px) const override {
    return cairo::png_at_most_wide(png, max_width_px);
  }
};

}  // namespace
}  // namespace fibrodem::cairo

extern "C" __attribute__((visibility("default"))) const fibrodem::Drawing* fibrodem_drawing_v3() {
  static const fibrodem::cairo::CairoDrawing drawing;
  return &drawing;
}
