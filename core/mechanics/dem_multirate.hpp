// Multirate DEM stepping (spec `multirate`; dem_solver.hpp, "Multirate";
// the scheme: dem_multirate_step.cpp): the light bodies (fibroblast disks
// whose critical step is below the clumps') take n substeps of each step,
// the heavy ones one. This part holds the classification, the boundary
// (the heavy bodies with a contact to a light one), the substeps' scratch
// and the fields a checkpoint carries; the contacts that touch a light body
// (fast contacts) come first in each contact set (fast_bonds, fast_contacts
// of them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/checkpoint_file.hpp"
#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_contacts.hpp"

namespace fibrodem {

class DemMultirate {
 public:
  bool on() const { return !light_.empty(); }
  const std::vector<std::uint8_t>& light() const { return light_; }  // per body (empty while off)
  // The contacts' order (fast first while on).
  ContactOrder order(const DemBodies& bodies) const { return {on() ? light_.data() : nullptr, bodies.pbody.data()}; }
  // Light: the free disks whose critical step (on the contacts and masses
  // now) is below the least of the free clumps'. Returns false, and stays
  // off, without such a disk or without a clump in contact; else puts the
  // contacts in its order (the caller indexes them and sets the step).
  bool start(const DemBodies& bodies, DemContacts& contacts);
  // After the contacts changed: the fast contacts, the boundary, the heavy
  // bodies' parts.
  void index(const DemBodies& bodies, const DemContacts& contacts);
  // The steps from the least critical steps of the heavy bodies, the clumps
  // and the light bodies, the heavy ones' stable step given (and maybe cut).
  void fit_steps(double& stable_step_ms, double safety_factor, double heavy_crit_s, double clump_crit_s,
                 double light_crit_s, const DemBodies& bodies, const DemContacts& contacts);
  // At a step's end, if a heavy disk's critical step fell below the clumps':
  // those disks made light and the contacts reordered; returns true if any
  // changed (the caller indexes the contacts and sets the step).
  bool reclassify_pending() const { return reclassify_pending_; }
  bool reclassify(const DemBodies& bodies, DemContacts& contacts);
  // Contact c (bonds first, then unbonded) touches a light body.
  bool fast_index(std::size_t c, std::size_t nbonds) const {
    return c < nbonds ? c < fast_bonds_ : c - nbonds < fast_contacts_;
  }

  // The scheme's step (dem_multirate_step.cpp): the heavy bodies' first half
  // (every body's pose at the start kept); substep j of n of h_s; the heavy
  // bodies' forces and closing half kick. The substeps' count: substeps_of.
  static std::size_t substeps_of(double dt_s, double light_step_s);
  void move_heavy_bodies(DemBodies& bodies, double dt_s);
  void light_substep(DemBodies& bodies, DemContacts& contacts, std::size_t j, std::size_t n, double h_s);
  void heavy_forces_and_kick(DemBodies& bodies, DemContacts& contacts, double dt_s, std::size_t n);
  void count_substeps(std::size_t n) { substeps_ += n; }

  // A body's centroid at the step's start (the strain's velocities of bodies).
  const std::vector<double>& bx_start() const { return bx_start_; }
  const std::vector<double>& by_start() const { return by_start_; }

  std::size_t light_bodies() const { return light_bodies_.size(); }
  std::size_t substeps() const { return substeps_; }
  double light_step_s() const { return light_step_s_; }
  std::size_t fast_bonds() const { return fast_bonds_; }
  std::size_t fast_contacts() const { return fast_contacts_; }

  // Checkpoint fields "dem.multirate" (light step, substeps) and
  // "dem.multirate.light"; load puts the contacts in its order (a no-op on
  // a checkpoint written with multirate) and throws CheckpointError.
  void save(CheckpointFields& fields) const;
  void load(const CheckpointFields& fields, const DemBodies& bodies, DemContacts& contacts);

 private:
  void list_light_bodies(const DemBodies& bodies);
  void move_light_disk(DemBodies& bodies, std::size_t k, double h_s) const;
  void sum_forces_and_kick_light_disk(DemBodies& bodies, const DemContacts& contacts, std::size_t k,
                                      double h_s) const;
  void add_fast_forces_of_boundary(const DemBodies& bodies, const DemContacts& contacts, std::size_t k, double w,
                                   bool last);

  // Light bodies (1; a heavy disk whose contacts make its critical step
  // shorter than the clumps' becomes light, never back) and their list,
  // each with its one particle (light bodies are disks); heavy bodies with
  // a contact to a light one (the boundary).
  std::vector<std::uint8_t> light_;
  std::vector<int> light_bodies_, light_particle_, boundary_bodies_;
  // The boundary's particles that touch a light body (placed each substep),
  // and each boundary body's fast contacts (CSR over boundary_bodies_:
  // ContactIncidence entries and the particle of each).
  std::vector<int> boundary_particles_, boundary_entry_start_, boundary_entry_, boundary_entry_particle_;
  // Each body's pose at the step's start, the heavy particles' places at its
  // end, and the heavy bodies' sums of the substeps' forces.
  std::vector<double> bx_start_, by_start_, br_start_, px_end_, py_end_;
  std::vector<double> fast_fx_, fast_fy_, fast_tq_;
  // The loops over the heavy bodies' parts: their move, and their force sums.
  std::vector<std::size_t> heavy_part_first_body_, heavy_sum_part_first_body_;
  std::size_t fast_bonds_ = 0, fast_contacts_ = 0, substeps_ = 0;
  bool reclassify_pending_ = false;  // a heavy disk's critical step fell below the clumps'
  double light_step_s_ = 0;          // the light bodies' stable step
};

}  // namespace fibrodem
