// The cells driving the DEM tissue mechanics: the mechanics steps at its own
// step up to the end of each cell step, each DEM step given the cells'
// lengths relative to rest (SL / SL_rest) interpolated linearly in time
// across the cell step. Back to the cells flows, if asked
// (track_fibre_stretch), each cell's fibre stretch in the deformed tissue at
// the end of each advance, for the stretch-activated current of the next
// cell step. It keeps the peak strain and the smallest DEM step taken, for
// summary.json.
//
// Rest (docs/topics/mechanics.md#rest; spec `skip_at_rest`): the DEM is not stepped
// while the tissue is at rest and its drive does not change. It falls asleep
// at the end of a cell step when every cell's length ratio is within
// kDriveTolerance of what the DEM last stepped with and its fastest body
// (MechanicsSolver::fastest_motion: speed v, acceleration a) could not move
// kRestDistance of the smallest particle radius over the skip: v T + a T^2 / 2
// for T from the moment it fell asleep. Its clock then advances by its steps
// without taking them (the same step times as an uninterrupted run), and its
// state, strain and particles stay as they were. It wakes, at once, at the
// first cell step whose lengths leave that tolerance or whose end would take
// T past that distance, and resumes from its frozen state with the lengths
// interpolated from those it last saw to the cells' present ones.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "integrate/cell_system.hpp"
#include "io/checkpoint_file.hpp"
#include "measure/cell_strain.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "run/rank_layout.hpp"
#include "tissue/tissue.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

class MechanicsCoupling {
 public:
  // A cell's length ratio may drift this far from what the DEM last saw
  // without waking it: 1e-4 of a Fig. 3 twitch's ~10 % shortening, 2 % of
  // the peak strain of a small sheet that barely contracts (~5e-4); the
  // Fig. 3 cells at rest under Rush-Larsen drift by ~5e-6 in 130 ms
  // (docs/topics/mechanics.md#rest).
  static constexpr double kDriveTolerance = 1e-5;
  // Asleep, no body may have been able to move this fraction of the
  // smallest particle radius: about the motion the drive's tolerance
  // ignores (1e-5 of a myocyte's length moves its end pebbles by ~4.5e-5 of
  // their radius), so neither criterion is the stricter one by orders of
  // magnitude; less would keep a tissue that rings at the scale of round-off
  // awake (a light fibroblast disk accelerates at ~1e-3 m/s^2 under
  // forces of 1e-11 N, and v T + a T^2 / 2 cannot tell that it only rings).
  static constexpr double kRestDistance = 1e-4;

  // Throws ManifestError at "mechanics" for a tissue or spec the solver cannot take.
  MechanicsCoupling(const Tissue& tissue, const DemSpec& spec);

  // Mechanics at its own step up to t_ms (the end of a cell step).
  void advance(double t_ms, const CellSystem& system) { advance(t_ms, system.stretch_by_cell()); }
  // The same from every cell's length relative to rest at t_ms (by tissue
  // number): what a run split over ranks gathers on rank 0
  // (run/mechanics_over_ranks.hpp).
  void advance(double t_ms, const std::vector<double>& length_ratio_by_cell);

  // The coupling's state and the solver's, for a checkpoint at the cells'
  // time; restore() throws CheckpointError if the mechanics' time does not
  // match start_ms.
  void save(CheckpointFields& fields) const;
  void restore(const CheckpointFields& fields, double start_ms);

  // Split over the ranks of one run (docs/guide/parallel.md, "The DEM over
  // ranks"): the solver steps each rank's own cells' bodies
  // (MechanicsSolver::split_over_ranks; cell_rank: every cell's rank), and
  // every call below is collective: advance (its rest decisions are every
  // rank's), save (rank 0 gathers every body, contact and cell length and
  // writes them) and restore (every rank reads the checkpoint itself).
  // `layout`: every rank's cells (the run's partition, run/rank_layout.hpp;
  // it must outlive this). Throws ManifestError at "mechanics" for a spec
  // the solver cannot split.
  void split_over_ranks(RankGroup& ranks, const RankLayout& layout);
  bool split() const { return ranks_ != nullptr; }

  // From now on, each advance ends by measuring every cell's fibre stretch
  // (measure/cell_strain.hpp) from the particles where they are. (Split
  // over ranks, a rank's own cells' are right: their neighbours are bonded
  // to them, so each is a body of the rank's or a ghost, current after
  // every step; the rest of its particles are as last shared.)
  void track_fibre_stretch(const Tissue& tissue);
  // By tissue cell number, as of the last advance that stepped (1 before
  // the first); NaN where the strain is unresolved; empty unless tracked.
  const std::vector<double>& fibre_stretch() const;

  MechanicsSolver& solver() { return *solver_; }
  const MechanicsSolver& solver() const { return *solver_; }
  double smallest_step_ms() const { return step_ms_; }
  double seconds() const { return seconds_; }  // wall time in advance()
  const std::array<double, 3>& peak_strain() const { return peak_strain_; }
  // DEM steps not taken at rest, and the time they span [ms]; asleep now.
  std::size_t skipped_steps() const { return skipped_steps_; }
  double slept_ms() const { return slept_ms_; }
  bool asleep() const { return asleep_; }
  // The solver's line for run.log and the steps skipped at rest.
  std::string report() const;

 private:
  void step_to(double t_ms);
  void skip_to(double t_ms);
  bool drive_unchanged(const std::vector<double>& length_ratio) const;
  std::vector<double> on_rank0(const std::vector<double>& by_cell) const;
  void keep_own_lengths();
  bool still_at_rest(double t_ms) const;
  void fall_asleep_if_at_rest();

  std::unique_ptr<MechanicsSolver> solver_;
  // Split over ranks: the ranks, and the run's layout of every rank's cells
  // (split_over_ranks).
  RankGroup* ranks_ = nullptr;
  const RankLayout* layout_ = nullptr;
  mutable std::vector<double> every_rank_;  // a reduction's values, one a rank (made once)
  double step_ms_ = 0, time_ms_ = 0, seconds_ = 0;
  // Cells' lengths relative to rest at the last cell step's start and end,
  // and as handed to a DEM step between them.
  std::vector<double> length_ratio_from_, length_ratio_to_, length_ratio_;
  double length_ratio_from_ms_ = 0;
  std::array<double, 3> peak_strain_{0, 0, 0};
  std::unique_ptr<CellStrain> cell_strain_;  // tracking the fibre stretch

  // Rest: the spec's switch; the distance no body may have been able to move
  // asleep [m]; the lengths the DEM last stepped with (length_ratio_ after a
  // step); whether it stepped since it was last asked for its motion; asleep,
  // since when and at what motion; the steps skipped and their time.
  bool skip_at_rest_ = true;
  double rest_distance_m_ = 0;
  bool motion_unknown_ = true;
  bool asleep_ = false;
  double asleep_since_ms_ = 0;
  MechanicsSolver::Motion asleep_motion_;
  std::size_t skipped_steps_ = 0, skipped_this_sleep_ = 0;
  double slept_ms_ = 0;
};

}  // namespace fibrodem
