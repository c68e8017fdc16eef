#include "io/drawing.hpp"

#include "io/plot_svg.hpp"
#include "util/runtime_module.hpp"

#include <stdexcept>

namespace fibrodem {

const Drawing& drawing() {
  static const Drawing& opened =
      module_object<Drawing>("drawing", kDrawingEntry, "needed to draw pictures and plots");
  return opened;
}

// The public drawing functions, through the module.

void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                    const PlotOptions& options) {
  drawing().write_plot_png(panels, file, options);
}

std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options, const std::string& id_prefix) {
  return drawing().plot_svg(panels, options, id_prefix);
}

void write_tissue_png(const Tissue& tissue, const std::filesystem::path& file, const std::vector<double>* values,
                      const PictureOptions& options) {
  if (values && values->size() != tissue.cell_count())
    throw std::runtime_error("write_tissue_png: " + std::to_string(values->size()) + " values for " +
                             std::to_string(tissue.cell_count()) + " cells");
  drawing().write_tissue_png(tissue, tissue.bounds_um(), file, values, options);
}

}  // namespace fibrodem
