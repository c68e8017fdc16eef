#include "io/tissue_imprint.hpp"

#include <algorithm>

namespace fibrodem {

PictureFrame imprint_frame(const std::array<double, 4>& bounds_um) {
  PictureOptions titled;
  titled.title = "t";
  return picture_frame(bounds_um, titled, true);
}

TissueImprinter::TissueImprinter(const std::array<double, 4>& bounds_um, const std::vector<CellType>& type)
    : type_(type), imprint_(std::make_shared<TissueImprint>()) {
  CellRaster& raster = imprint_->picture;
  const PictureFrame& f = raster.frame = imprint_frame(bounds_um);
  raster.cell.assign(static_cast<std::size_t>(f.width_px) * static_cast<std::size_t>(f.height_px), -1);
}

// Each pixel takes the cell of the last particle covering its centre: the
// particles in their order, each overwriting the pixels it covers, as the
// unantialiased picture paints them. The cells are kept run by run.
void TissueImprinter::add(const Particle& p) {
  CellRaster& raster = imprint_->picture;
  const PictureFrame& f = raster.frame;
  for_each_disk_span(f.width_px, f.height_px, f.x_px(p.x_um), f.y_px(p.y_um), f.radius_px(p.r_um),
                     [&](int y, int x0, int x1) {
                       auto* row = raster.cell.data() + static_cast<std::size_t>(y) * f.width_px;
                       std::fill(row + x0, row + x1 + 1, p.cell);
                     });
  ParticleCellRuns& runs = imprint_->cells;
  if (runs.cell.empty() || runs.cell.back() != p.cell) {
    runs.cell.push_back(p.cell);
    runs.end.push_back(0);
  }
  runs.end.back() = static_cast<std::int32_t>(++particles_);
  vtp_.add(p, type_[static_cast<std::size_t>(p.cell)]);
}

std::shared_ptr<const TissueImprint> TissueImprinter::finish() {
  imprint_->cells.cell.shrink_to_fit();
  imprint_->cells.end.shrink_to_fit();
  imprint_->vtp = vtp_.finish();
  return std::move(imprint_);
}

std::shared_ptr<const TissueImprint> imprint_tissue(const Tissue& tissue) {
  TissueImprinter imprinter(tissue.bounds_um(), tissue.type);
  for (const Particle& p : tissue.particles) imprinter.add(p);
  return imprinter.finish();
}

std::size_t TissueImprint::bytes() const {
  return sizeof(std::int32_t) * (picture.cell.size() + cells.cell.size() + cells.end.size()) + vtp.bytes();
}

}  // namespace fibrodem
