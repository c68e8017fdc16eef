#include "io/tissue_imprint.hpp"

#include <algorithm>

namespace fibrodem {

PictureFrame imprint_frame(const std::array<double, 4>& bounds_um) {
  PictureOptions titled;
  titled.title = "t";
  return picture_frame(bounds_um, titled, true);
}

namespace {

// Each pixel the cell of the last particle covering its centre: the
// particles in their order, each overwriting the pixels it covers, as the
// unantialiased picture paints them.
CellRaster rasterise(const Tissue& tissue) {
  CellRaster raster;
  const PictureFrame& f = raster.frame = imprint_frame(tissue.bounds_um());
  raster.cell.assign(static_cast<std::size_t>(f.width_px) * static_cast<std::size_t>(f.height_px), -1);
  for (const Particle& p : tissue.particles)
    for_each_disk_span(f.width_px, f.height_px, f.x_px(p.x_um), f.y_px(p.y_um), f.radius_px(p.r_um),
                       [&](int y, int x0, int x1) {
                         auto* row = raster.cell.data() + static_cast<std::size_t>(y) * f.width_px;
                         std::fill(row + x0, row + x1 + 1, p.cell);
                       });
  return raster;
}

ParticleCellRuns cell_runs(const Tissue& tissue) {
  ParticleCellRuns runs;
  for (std::size_t p = 0; p < tissue.particles.size(); ++p) {
    const std::int32_t cell = tissue.particles[p].cell;
    if (runs.cell.empty() || runs.cell.back() != cell) {
      runs.cell.push_back(cell);
      runs.end.push_back(0);
    }
    runs.end.back() = static_cast<std::int32_t>(p + 1);
  }
  runs.cell.shrink_to_fit();
  runs.end.shrink_to_fit();
  return runs;
}

}  // namespace

std::shared_ptr<const TissueImprint> imprint_tissue(const Tissue& tissue) {
  auto imprint = std::make_shared<TissueImprint>();
  imprint->picture = rasterise(tissue);
  imprint->cells = cell_runs(tissue);
  imprint->vtp = pack_vtp_geometry(tissue);
  return imprint;
}

std::size_t TissueImprint::bytes() const {
  return sizeof(std::int32_t) * (picture.cell.size() + cells.cell.size() + cells.end.size()) + vtp.bytes();
}

}  // namespace fibrodem
