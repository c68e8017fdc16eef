// Pictures and plots are drawn by the drawing module (libfibrodem-drawing.so,
// modules/drawing/, on Cairo), opened on the first picture: a run that draws
// nothing never loads Cairo and its libraries (docs/topics/performance.md#start-up).
// This is the module's interface; the core's public drawing functions
// (io/plot_png.hpp, io/plot_svg.hpp, io/tissue_picture.hpp,
// report/snapshot_frames.hpp) call it.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "io/plot_png.hpp"
#include "io/tissue_picture.hpp"

namespace fibrodem {

class Drawing {
 public:
  virtual ~Drawing() = default;
  virtual void write_plot_png(const std::vector<PlotPanel>& panels, const std::filesystem::path& file,
                              const PlotOptions& options) const = 0;
  virtual std::string plot_svg(const std::vector<PlotPanel>& panels, const PlotOptions& options,
                               const std::string& id_prefix) const = 0;
  // bounds_um: tissue.bounds_um() (the module calls no code of the core).
  virtual void write_tissue_png(const Tissue& tissue, const std::array<double, 4>& bounds_um,
                                const std::filesystem::path& file, const std::vector<double>* cell_values,
                                const PictureOptions& options) const = 0;
  virtual std::string png_at_most_wide(const std::filesystem::path& png, int max_width_px) const = 0;
};

// The module's entry point, exported as C (bump its version with any change
// to Drawing, so an older module is refused rather than misread).
inline constexpr const char* kDrawingEntry = "fibrodem_drawing_v3";

// The module's Drawing, opened on the first call (thread-safe). Throws
// std::runtime_error if the module is missing (util/runtime_module.hpp).
const Drawing& drawing();

}  // namespace fibrodem
