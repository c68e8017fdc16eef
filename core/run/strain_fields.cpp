#include "run/strain_fields.hpp"

#include <spdlog/fmt/fmt.h>

#include "run/frame_log.hpp"

namespace fibrodem {

void StrainFields::add_frame(double t_ms) {
  const std::vector<double>& stretch = strain_.field().fibre_stretch;
  if (!ranks_) return frames_.add(t_ms, stretch);
  gather_by_cell(*ranks_, *layout_, stretch, own_, gathered_, by_cell_);
  if (ranks_->rank() == 0) frames_.add(t_ms, by_cell_);
}

void StrainFields::split_over(RankGroup& ranks, const RankLayout& layout) {
  ranks_ = &ranks;
  layout_ = &layout;
}

void StrainFields::read_back(const std::filesystem::path& file, std::size_t count, std::size_t to_come) {
  StretchFrames read(frames_.cells);
  read.reserve_more(count + to_come);
  read_frame_log(file, count, read);
  frames_ = std::move(read);
}

void StrainFields::sample_now(double t_ms, const MechanicsSolver& mechanics) {
  now(mechanics);
  add_frame(t_ms);
}

void StrainFields::due(double t_ms, double w, const MechanicsSolver& mechanics) {
  if (pending_.empty()) at_step_start_ = mechanics.particles();
  pending_.emplace_back(t_ms, w);
}

void StrainFields::complete(const MechanicsSolver& mechanics) {
  if (pending_.empty()) return;
  const std::vector<Particle>& at_end = mechanics.particles();
  interpolated_ = at_step_start_;
  for (const auto& [t, w] : pending_) {
    for (std::size_t p = 0; p < interpolated_.size(); ++p) {
      interpolated_[p].x_um = at_step_start_[p].x_um + w * (at_end[p].x_um - at_step_start_[p].x_um);
      interpolated_[p].y_um = at_step_start_[p].y_um + w * (at_end[p].y_um - at_step_start_[p].y_um);
    }
    strain_.compute(interpolated_);
    add_frame(t);
  }
  pending_.clear();
}

std::unique_ptr<StrainFields> make_strain_fields(const Tissue& tissue, const OutputSpec& output,
                                                 std::vector<std::string>& notes) {
  const SnapshotSpec& snap = output.snapshots;
  if (!(output.reentry.on || (snap.every_ms > 0 && (snap.vtk || snap.strain)))) return nullptr;
  auto fields = std::make_unique<StrainFields>(tissue);
  if (const std::size_t n = fields->unresolved_cells(); n > 0)
    notes.push_back(fmt::format("per-cell strain: {} of {} cells have neighbours that do not span the plane "
                                "(fewer than two, or all on one line through the cell): their strain is NaN",
                                n, tissue.cell_count()));
  return fields;
}

}  // namespace fibrodem
