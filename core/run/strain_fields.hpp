// The cells' strain during a run with mechanics (measure/cell_strain.hpp),
// computed only where an output asks for it: at each snapshot (the VTK
// files' strain fields and, with output.snapshots.strain, the strain
// picture), and with output.reentry at each re-entry sample, whose fibre
// stretch gives each phase singularity's (phase_singularities.csv).
//
// A re-entry sample's V is interpolated between the ends of the cell step
// that holds its time (run/simulation_outputs.cpp); its strain is that of
// the cells' centroids interpolated alike, between the DEM's particles at
// the step's start and at its end (the DEM steps to the end of each cell
// step after V is sampled: the sample is taken in two halves, due() before
// the DEM steps and complete() after).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "measure/cell_frames.hpp"
#include "measure/cell_strain.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "run/rank_layout.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

class StrainFields {
 public:
  explicit StrainFields(const Tissue& tissue) : strain_(tissue), frames_(tissue.cell_count()) {}

  // The field with the DEM's particles as they are now.
  const CellStrainField& now(const MechanicsSolver& mechanics) { return strain_.compute(mechanics.particles()); }
  // Cells whose neighbours do not span the plane (NaN strain).
  std::size_t unresolved_cells() const { return strain_.unresolved_cells(); }

  // Re-entry samples: one at t with the DEM as it is now; one at t, a
  // fraction w into a cell step whose start the DEM is still at (due), taken
  // once the DEM has reached the step's end (complete).
  void sample_now(double t_ms, const MechanicsSolver& mechanics);
  void due(double t_ms, double w, const MechanicsSolver& mechanics);
  void complete(const MechanicsSolver& mechanics);
  const StretchFrames& stretch_frames() const { return frames_; }
  // Room for this many more samples (CellFrames::reserve_more), where frames are held.
  void reserve_samples(std::size_t samples) {
    if (!ranks_ || ranks_->rank() == 0) frames_.reserve_more(samples);
  }
  // Split over ranks with the DEM (DemSolver::split_over_ranks): a rank's
  // bodies and ghosts keep its own cells' particles and their neighbours'
  // current, so each rank takes its own cells' stretch at a sample and rank
  // 0 gathers the frame in tissue order (the same values as one process's,
  // to the DEM's rounding); only rank 0 holds frames. Every rank then takes
  // the samples at the same times (each a collective gather).
  void split_over(RankGroup& ranks, const RankLayout& layout);
  // A resumed run: the first `count` stretch frames of the log `file`
  // (run/frame_log.hpp) in place of those held, with room for `to_come`
  // more. Throws CheckpointError naming the file, the frames held unchanged.
  void read_back(const std::filesystem::path& file, std::size_t count, std::size_t to_come);

 private:
  void add_frame(double t_ms);

  CellStrain strain_;
  StretchFrames frames_;
  RankGroup* ranks_ = nullptr;  // split over ranks (split_over), else null
  const RankLayout* layout_ = nullptr;
  std::vector<double> own_, gathered_, by_cell_;  // a split sample's own cells', rank 0's gathered and by cell
  std::vector<Particle> at_step_start_, interpolated_;  // particles (no allocation after the first sample)
  std::vector<std::pair<double, double>> pending_;      // (t, w) of the samples due in this step
};

// The run's strain fields, if its outputs ask for them (snapshots with VTK
// files or strain pictures, output.reentry), else null; for a run with
// mechanics. Notes how many cells have no strain (NaN), if any.
std::unique_ptr<StrainFields> make_strain_fields(const Tissue& tissue, const OutputSpec& output,
                                                 std::vector<std::string>& notes);

}  // namespace fibrodem
