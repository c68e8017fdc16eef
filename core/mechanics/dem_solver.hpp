// `dem`: the seed paper's DEM tissue mechanics (docs/reference/references.md#dem).
//
// Bodies: a myocyte is a rigid clump of its N collinear particles (centroid,
// angle, velocity, spin; mass and polar inertia of the union of its disks at
// rest, density x area x 1 m: 2D disks of unit thickness); it contracts along
// its axis: at length ratio lambda the spacing and radius follow the spec's
// length mode and area rule (clump_geometry.hpp), the centroid and axis stay.
// A fibroblast particle is a rigid disk of constant radius, free (or fixed with
// `fibroblasts_fixed`); the particles of a multi-particle fibroblast are
// separate disks held by their bonds. A collagen particle (of no cell) is a
// free disk too; contacts with one, and the tissue's bonds through collagen,
// take mechanics.collagen_stiffness_factor.
//
// Contacts: the tissue's bonds (formed at the start, never re-formed; they can
// break), and, with `contact_detection`, the contacts between particles that
// were not bonded, found on a Verlet list (contact_detector.hpp) and given the
// law's unbonded state (PFC's linear model: repulsion and dashpots while they
// overlap). Both in SoA order, their law called once per block of 512.
// Contact point velocities include a pebble's motion along the clump's axis
// from contraction (so dashpots and shear springs see it).
//
// Motion: velocity Verlet (PFC 6+; the same positions as PFC 5's centred
// differences): half kick, drift, new geometry at the length ratios set, forces,
// half kick. Dashpots see the half-step velocities; PFC's local damping
// (optional) acts in the kicks.
//
// Strain: each step, alpha = (sum V~ x~^T)(sum x~ x~^T)^+ over all particles
// (or bodies), V the half-step velocity (x^{n+1} - x^n)/dt of each, x its
// midpoint (x^n + x^{n+1})/2, so a rigid motion gives exactly zero; eps +=
// sym(alpha) dt. Bodies on one line (a straight strand) define only the
// stretch along it: that is all the strain they get.
//
// Stable step: safety x min over free bodies of sqrt(m / k_t), sqrt(I / k_r),
// k_t = sum (kn' + ks'), k_r = sum kn' (rho x n)^2 + ks' (rho x t)^2 over the
// body's bonds, rho from its centroid to the contact point, k' the law's
// dashpot-corrected stiffness (docs/reference/references.md#dem-timestep), at rest geometry.
// Mass scaling (spec `mass_scaling` f > 0; PFC's density scaling, Itasca
// PFC 6, "Timestep Determination"): every body whose critical step is below
// a target H gets the mass kt H^2 (and inertia kr H^2), with each contact
// list; H is set once, on the contacts at the start, the longest for which
// the mass (and the inertia) so added is at most f of the tissue's. The
// dashpots keep the masses of the bodies' density (they set the tissue's
// viscous forces). Quasi-static loading only: the added mass slows the
// tissue's own motion (dem_mass_scaling.hpp; docs/topics/mechanics.md).
//
// Multirate (spec `multirate`; dem_multirate.hpp): the bodies whose critical
// step is below the clumps' (the light ones: small fibroblast disks) take
// n substeps of each step, the others (heavy) one; heavy particles are
// interpolated over the step for the substeps' contacts, and the heavy bodies
// get those contacts' mean force over the substeps.
//
// Threads (OpenMP's present count): a step is three parallel loops. The
// first moves each body and places its particles, summing the strain's and
// the contact list's fits over fixed parts of the bodies of about equal work
// (DemBodies::part_first_body; move_and_sum); the
// second is the list's check for a rebuild; the third computes each
// contact's force, block by block, into per-contact arrays, then sums them
// per particle and body in a fixed order (contact_incidence.hpp) and kicks
// the body. Each thread takes a contiguous run of the parts, so the
// particles it moves are mostly those its contact blocks read (dealing the
// parts out in turn made in-series tissue's two-thread DEM ~30 % slower). A
// loop that works on some bodies only has parts of its own: under multirate
// the heavy bodies' move and sums (DemMultirate::index), and the
// clumps' shapes (DemBodies::shape_part_first_body).
// Deterministic: the same bits for any number of threads; no allocation per
// step.
//
// Ranks (split_over_ranks; dem_split.hpp): each rank of a split run steps
// its own cells' bodies (the loops pass over the others: DemBodies::own)
// and the contacts that touch them (listed first in their sets), trading
// its border bodies with its neighbours after the move; the step's sums
// and the contact list's check are reduced over the ranks.
//
// Parts and files (each part with its own state; DemSolver owns them and
// orchestrates the step): DemBodies (dem_bodies.hpp: bodies, particles and
// their parts; dem_bodies.cpp, dem_reshape.cpp for the clumps' shapes),
// DemContacts (dem_contacts.hpp: bonds, the contact list, forces,
// incidences; dem_contacts.cpp, dem_contact_forces.cpp), DemMultirate
// (dem_multirate.hpp: the classes, boundary and scratch of the multirate
// scheme; dem_multirate.cpp, dem_multirate_step.cpp for its step),
// DemMassScaling (dem_mass_scaling.hpp), DemStrainFit (dem_strain.hpp),
// DemSplit (dem_split.hpp: over ranks). The
// per-body and per-particle pieces the step's loops inline:
// dem_step_inline.hpp. The solver itself: dem_solver.cpp (the step and its
// fused move loop), dem_stable_step.cpp, dem_checkpoint.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "mechanics/clump_geometry.hpp"
#include "mechanics/contact_law.hpp"
#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_contacts.hpp"
#include "mechanics/dem_mass_scaling.hpp"
#include "mechanics/dem_multirate.hpp"
#include "mechanics/dem_split.hpp"
#include "mechanics/dem_strain.hpp"
#include "mechanics/mechanics_solver.hpp"

namespace fibrodem {

class DemSolver final : public MechanicsSolver {
 public:
  // Throws std::invalid_argument for a myocyte whose particles are not
  // collinear, equally spaced and of one radius, a bond inside one clump, or a
  // spec dt_ms above the stable step.
  DemSolver(const Tissue& tissue, const DemSpec& spec);

  double stable_step_ms() const override { return stable_step_ms_; }
  void set_cell_length_ratios(const std::vector<double>& ratio) override;
  void step(double dt_ms) override;
  std::array<double, 3> strain() const override { return strain_fit_.strain(); }
  const std::vector<Particle>& particles() const override;
  std::string report() const override;
  // One pass over the bodies (not part of a step: asked for only when the
  // coupling needs it).
  Motion fastest_motion() const override;
  void save(CheckpointFields& fields) const override;
  void load(const CheckpointFields& fields) override;
  // Split over ranks (dem_split.hpp); refuses multirate, whose substeps are
  // not split.
  void split_over_ranks(RankGroup& ranks, const std::vector<int>& cell_rank) override;
  void gather_on_rank0(bool whole_state) override;
  void count_on_rank0() override;
  bool split() const { return split_ != nullptr; }

  double step_ms() const override { return spec_.dt_ms > 0 ? spec_.dt_ms : stable_step_ms_; }
  const DemSpec& spec() const { return spec_; }
  double time_ms() const { return time_s_ * 1e3; }
  std::size_t steps() const { return steps_; }

  // Bodies (SI): clumps and disks, in order of their first particle.
  struct BodyState {
    double x_m, y_m, theta_rad, vx_m_per_s, vy_m_per_s, omega_rad_per_s;
    double mass_kg, inertia_kg_m2;
    int cell;
    bool clump, fixed;
  };
  std::size_t body_count() const { return bodies_.size(); }
  BodyState body(std::size_t b) const;
  int body_of_particle(std::size_t p) const { return bodies_.pbody[p]; }
  // Sets a body's velocity and spin (SI); ignored for a fixed body.
  void set_body_velocity(std::size_t b, double vx_m_per_s, double vy_m_per_s, double omega_rad_per_s);
  // Each myocyte's present clump shape (pebble radius and spacing, um); {0,0} for a fibroblast.
  ClumpShape cell_shape_um(int cell) const { return bodies_.cell_shape_um(cell); }

  const BondSet& bonds() const { return contacts_.bonds; }
  std::size_t broken_bonds() const { return counted_now() ? counted_[0] : contacts_.broken_bonds(); }
  // Unbonded contacts on the present Verlet list (empty without detection),
  // how many of them touch, and how often the list was built.
  const BondSet& contacts() const { return contacts_.contacts; }
  std::size_t touching_contacts() const { return counted_now() ? counted_[1] : contacts_.touching_contacts(); }
  std::size_t contact_list_builds() const { return contacts_.list_builds(); }
  // Mass scaling: how many bodies it made heavier, and the fraction of the
  // tissue's mass and polar inertia it added (0 without).
  std::size_t scaled_bodies() const { return mass_scaling_.scaled_bodies(); }
  double added_mass_fraction() const { return mass_scaling_.added_mass_fraction(); }
  double added_inertia_fraction() const { return mass_scaling_.added_inertia_fraction(); }
  // Multirate: how many bodies take substeps, the substeps taken in all,
  // and the light bodies' stable step [ms] (0 without multirate).
  std::size_t light_bodies() const { return multirate_.light_bodies(); }
  std::size_t substeps() const { return multirate_.substeps(); }
  double light_step_ms() const { return multirate_.light_step_s() * 1e3; }
  // Energies at the last full step [J] (unit thickness): kinetic (translation +
  // rotation) and elastic (springs of the active contacts, 1/2 F^2 / k).
  double kinetic_energy_J() const { return bodies_.kinetic_energy_J(); }
  double elastic_energy_J() const { return contacts_.elastic_energy_J(); }

 private:
  static constexpr std::size_t kStepParts = DemBodies::kStepParts;
  // The longest DEM step [ms]: cells' lengths change over ms, and at the ~um/ms
  // speeds of contracting tissue a body moves less than the contact skin in it.
  static constexpr double kLongestStep_ms = 1.0;
  struct StepSums {
    DemStrainFit::Sums strain;
    ContactDetector::FitSums fit;
  };
  template <bool kMove>
  StepSums move_and_sum(double dt_s);
  void update_list_and_strain(const StepSums& sums, double dt_s);
  void step_multirate(double dt_s);
  void compute_forces_and_kick(double dt_s, double h_s);
  void rebuild_contacts();
  void index_contacts();
  ContactOrder contact_order() const;
  bool list_needs_rebuild(const StepSums& sums);
  void reduce_over_ranks(StepSums& sums);
  void compute_stable_step();

  DemSpec spec_;
  DemContacts contacts_;  // (before the bodies: an unknown law is named first)
  DemBodies bodies_;
  DemMultirate multirate_;
  DemMassScaling mass_scaling_;
  DemStrainFit strain_fit_;
  std::unique_ptr<DemSplit> split_;  // over ranks; null in one process

  double stable_step_ms_ = 0;
  double bonded_stable_step_ms_ = 0;  // at the start (a loaded checkpoint's is checked against it)
  double time_s_ = 0;
  std::size_t steps_ = 0;

  mutable std::vector<Particle> out_;
  mutable bool out_dirty_ = true;
  // Split: broken bonds and touching contacts summed over the ranks
  // (count_on_rank0), valid at the step they were counted at.
  std::array<std::size_t, 2> counted_{};
  std::size_t counted_at_step_ = static_cast<std::size_t>(-1);
  bool counted_now() const { return split_ && counted_at_step_ == steps_; }
};

}  // namespace fibrodem
