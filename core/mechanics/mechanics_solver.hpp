// A MechanicsSolver moves the tissue's bodies (DEM: rigid myocyte clumps and
// fibroblast disks) under the forces of its contacts, driven by the cells'
// lengths, and reports the tissue's strain (docs/dev/architecture.md#interfaces).
// Units at this boundary: ms, um; inside the solver SI.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/checkpoint_file.hpp"
#include "mechanics/contact_law.hpp"
#include "mechanics/dem_spec.hpp"
#include "tissue/tissue.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

class MechanicsSolver {
 public:
  virtual ~MechanicsSolver() = default;
  // The largest step [ms] at which the explicit scheme is stable (with the
  // dashpot correction and the safety factor); step() refuses a larger one.
  virtual double stable_step_ms() const = 0;
  // The step to take next [ms]: the spec's dt_ms, or else the stable step,
  // which may change as contacts form and part (ask before each step).
  virtual double step_ms() const = 0;
  // Sets each cell's length relative to rest (1 = rest; one value per cell,
  // fibroblasts' ignored), e.g. SL / SL_rest. It takes effect in the next
  // step(), as the length at the end of that step. Throws std::invalid_argument
  // (and changes nothing) for a wrong count or a myocyte ratio outside
  // [0.5, 1.5] or without a shape of the same area.
  virtual void set_cell_length_ratios(const std::vector<double>& ratio) = 0;
  // Advances the bodies by dt; throws std::invalid_argument if dt exceeds
  // stable_step_ms() (naming both).
  virtual void step(double dt_ms) = 0;
  // The tissue's accumulated average strain (sum of the symmetric part of the
  // least-squares velocity gradient times dt): eps_xx, eps_yy, eps_xy (tensor
  // component, not the engineering shear).
  virtual std::array<double, 3> strain() const = 0;
  // One line on what it did so far (steps, contacts, broken bonds), for run.log.
  virtual std::string report() const = 0;
  // Everything that evolves (bodies, contacts and their forces, contact
  // lists, strain, time), for a checkpoint; load() takes it back into a
  // solver built for the same tissue and spec, and throws CheckpointError
  // naming a field that does not fit.
  virtual void save(CheckpointFields& fields) const = 0;
  virtual void load(const CheckpointFields& fields) = 0;
  // Present particle positions and radii [um], in the tissue's order (snapshots).
  virtual const std::vector<Particle>& particles() const = 0;

  // How fast the fastest free body moves now (SI), to tell that the tissue
  // is at rest (run/mechanics_coupling.hpp): the largest speed of a point of
  // a body (|v| + |omega| x its reach, the farthest point of its particles
  // from its centroid) and the largest acceleration its unbalanced force and
  // torque give such a point (|F| / m + |T| / I x reach). Both 0 for a tissue
  // at rest under its present lengths.
  struct Motion {
    double speed_m_per_s = 0, acceleration_m_per_s2 = 0;
  };
  virtual Motion fastest_motion() const = 0;

  // Split over the ranks of one run (docs/guide/parallel.md, "The DEM over
  // ranks"): from now on each rank steps the bodies of its own cells
  // (cell_rank: every cell's rank, the same on every rank), and every call
  // that changes or reads the whole tissue is collective: every rank makes
  // it at the same point (step, fastest_motion, gather_on_rank0, load).
  // strain() is the whole tissue's on every rank. Throws
  // std::invalid_argument for a spec (or a solver) that cannot be split.
  virtual void split_over_ranks(RankGroup& /*ranks*/, const std::vector<int>& /*cell_rank*/) {
    throw std::invalid_argument("this mechanics solver cannot be split over ranks");
  }
  // Split: every body's present state on rank 0, for particles() there
  // (and, with whole_state, everything save() writes). Collective; nothing
  // in one process.
  virtual void gather_on_rank0(bool /*whole_state*/) {}
  // Split: the counts the solver's report gives of its contacts, summed
  // over each rank's own onto rank 0, without gathering every contact's
  // state (the run's last log line). Collective; nothing in one process.
  virtual void count_on_rank0() {}
};

// The spec's solver (`dem`) for a tissue; throws std::invalid_argument if the
// tissue or the spec cannot be simulated (e.g. dt_ms above the stable step).
std::unique_ptr<MechanicsSolver> make_mechanics_solver(const Tissue& tissue, const DemSpec& spec);

}  // namespace fibrodem
