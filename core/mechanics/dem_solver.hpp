// `dem`: the seed paper's DEM tissue mechanics (docs/references.md#dem).
//
// Bodies: a myocyte is a rigid clump of its N collinear particles (centroid,
// angle, velocity, spin; mass and polar inertia of the union of its disks at
// rest, density x area x 1 m: 2D disks of unit thickness); it contracts along
// its axis: at length ratio lambda the spacing and radius follow the spec's
// length mode and area rule (clump_geometry.hpp), the centroid and axis stay.
// A fibroblast particle is a rigid disk of constant radius, free (or fixed with
// `fibroblasts_fixed`); the particles of a multi-particle fibroblast are
// separate disks held by their bonds.
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
// dashpot-corrected stiffness (docs/references.md#dem-timestep), at rest geometry.
// Mass scaling (spec `mass_scaling` f > 0; PFC's density scaling, Itasca
// PFC 6, "Timestep Determination"): every body whose critical step is below
// a target H gets the mass kt H^2 (and inertia kr H^2), with each contact
// list; H is set once, on the contacts at the start, the longest for which
// the mass (and the inertia) so added is at most f of the tissue's. The
// dashpots keep the masses of the bodies' density (they set the tissue's
// viscous forces). Quasi-static loading only: the added mass slows the
// tissue's own motion (dem_mass_scaling.cpp; docs/mechanics.md).
//
// Multirate (spec `multirate`; dem_multirate.cpp): the bodies whose critical
// step is below the clumps' (the light ones: small fibroblast disks) take
// n substeps of each step, the others (heavy) one; heavy particles are
// interpolated over the step for the substeps' contacts, and the heavy bodies
// get those contacts' mean force over the substeps.
//
// Threads (OpenMP's present count): a step is three parallel loops. The
// first moves each body and places its particles, summing the strain's and
// the contact list's fits over fixed parts of the bodies of about equal work
// (partition_bodies; move_bodies); the
// second is the list's check for a rebuild; the third computes each
// contact's force, block by block, into per-contact arrays, then sums them
// per particle and body in a fixed order (contact_incidence.hpp) and kicks
// the body. Each thread takes a contiguous run of the parts, so the
// particles it moves are mostly those its contact blocks read (dealing the
// parts out in turn made in-series tissue's two-thread DEM ~30 % slower). A
// loop that works on some bodies only has parts of its own: under multirate
// the heavy bodies' move and sums (partition_heavy_bodies), and the
// clumps' shapes (partition_bodies).
// Deterministic: the same bits for any number of threads; no allocation per
// step.
//
// Files: dem_bodies.cpp (bodies built from the tissue), dem_reshape.cpp
// (clump shapes at the cells' length ratios), dem_solver.cpp (the step and
// its fused move loop), dem_step_inline.hpp (the per-body pieces it inlines),
// dem_contacts.cpp (bonds and the contact list), dem_contact_forces.cpp,
// dem_stable_step.cpp, dem_mass_scaling.cpp, dem_multirate.cpp (multirate
// steps), dem_strain.cpp, dem_checkpoint.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "mechanics/clump_geometry.hpp"
#include "mechanics/contact_detector.hpp"
#include "mechanics/contact_incidence.hpp"
#include "mechanics/contact_law.hpp"
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
  std::size_t body_count() const { return bx_.size(); }
  BodyState body(std::size_t b) const;
  int body_of_particle(std::size_t p) const { return pbody_[p]; }
  // Sets a body's velocity and spin (SI); ignored for a fixed body.
  void set_body_velocity(std::size_t b, double vx_m_per_s, double vy_m_per_s, double omega_rad_per_s);
  // Each myocyte's present clump shape (pebble radius and spacing, um); {0,0} for a fibroblast.
  ClumpShape cell_shape_um(int cell) const;

  const BondSet& bonds() const { return bonds_; }
  std::size_t broken_bonds() const;
  // Unbonded contacts on the present Verlet list (empty without detection),
  // how many of them touch, and how often the list was built.
  const BondSet& contacts() const { return contacts_; }
  std::size_t touching_contacts() const;
  std::size_t contact_list_builds() const { return detector_ ? detector_->builds() : 0; }
  // Mass scaling: how many bodies it made heavier, and the fraction of the
  // tissue's mass and polar inertia it added (0 without).
  std::size_t scaled_bodies() const { return scaled_bodies_; }
  double added_mass_fraction() const { return added_mass_fraction_; }
  double added_inertia_fraction() const { return added_inertia_fraction_; }
  // Multirate: how many bodies take substeps, the substeps taken in all,
  // and the light bodies' stable step [ms] (0 without multirate).
  std::size_t light_bodies() const { return light_bodies_.size(); }
  std::size_t substeps() const { return substeps_; }
  double light_step_ms() const { return light_step_s_ * 1e3; }
  // Energies at the last full step [J] (unit thickness): kinetic (translation +
  // rotation) and elastic (springs of the active contacts, 1/2 F^2 / k).
  double kinetic_energy_J() const;
  double elastic_energy_J() const;

 private:
  struct StepSums {
    DemStrainFit::Sums strain;
    ContactDetector::FitSums fit;
  };
  static constexpr std::size_t kStepParts = 64;  // fixed by the tissue, not the threads
  void add_bodies(const Tissue& tissue);
  void index_particles();
  void partition_bodies();
  void partition_force_sums();
  void partition_heavy_bodies();
  double move_work(std::size_t b) const;
  double sum_work(std::size_t b) const;
  std::vector<std::pair<int, int>> form_bonds(const Tissue& tissue);
  void kick_body(std::size_t b, double h_s);
  void drift_and_reshape(std::size_t b, double dt_s);
  void place_particles_of(std::size_t b);
  template <bool kMove>
  StepSums move_and_sum(double dt_s);
  void add_strain(const DemStrainFit::Sums& sums, double dt_s);
  void compute_forces_and_kick(double dt_s, double h_s);
  struct BlockScratch;
  void contact_block(BondSet& set, std::size_t begin, std::size_t count, std::size_t number, double dt_s,
                     BlockScratch& s);
  void sum_forces_on_body(std::size_t b);
  void index_contacts();
  void set_contact_constants(BondSet& set, std::size_t k, int p, int q) const;
  void rebuild_contacts();
  void compute_stable_step();
  void scale_masses();
  double scaling_target_step_s(double f) const;
  // Multirate stepping (dem_multirate.cpp).
  void step_multirate(double dt_s);
  void start_multirate();
  bool fast_contact(int p, int q) const {
    return !blight_.empty() && (blight_[pbody_[p]] || blight_[pbody_[q]]);
  }
  bool fast_index(std::size_t c) const {
    return c < bonds_.size() ? c < fast_bonds_ : c - bonds_.size() < fast_contacts_;
  }
  bool contact_order_less(int p1, int q1, int p2, int q2) const;
  std::size_t order_fast_first(BondSet& set, bool by_pairs) const;
  void fit_multirate_steps(double heavy_crit_s, double clump_crit_s, double light_crit_s);
  void reclassify_heavy_disks();
  void list_light_bodies();
  void partition_candidates_fast_first();
  void index_multirate();
  void load_multirate(const CheckpointFields& fields);
  void move_heavy_bodies(double dt_s);
  void light_substep(std::size_t j, std::size_t n, double h_s);
  void move_light_disk(std::size_t k, double h_s);
  void sum_forces_and_kick_light_disk(std::size_t k, double h_s);
  template <class Counted>
  void sum_particle_contacts(std::size_t i, Counted counted, double& fx, double& fy, double& tq) const;
  template <class Counted>
  void sum_body_contacts(std::size_t b, double gx, double gy, Counted counted, double (&f)[3]) const;
  void forces_of_contact_range(std::size_t bond_begin, std::size_t bond_end, std::size_t contact_begin,
                               std::size_t contact_end, double dt_s);
  void add_fast_forces_of_boundary(std::size_t k, double w, bool last);
  void heavy_forces_and_kick(double dt_s, std::size_t n);
  // Each evolving array with its checkpoint field's name, for save and load
  // alike (Self: DemSolver or const DemSolver).
  template <class Self, class F>
  static void for_each_evolving_array(Self& self, F&& f);

  static constexpr std::size_t kBlock = 512;

  DemSpec spec_;
  std::unique_ptr<BoundContactLaw> law_;
  std::size_t cells_ = 0;

  // Bodies (SoA, SI).
  std::vector<double> bx_, by_, bth_, bvx_, bvy_, bw_, bfx_, bfy_, btq_;
  // Masses and inertias of motion (mass scaling may have raised them), and
  // those of the bodies' density (the dashpots').
  std::vector<double> inv_m_, inv_i_, mass_, inertia_, density_mass_, density_inertia_;
  std::vector<int> bcell_;
  std::vector<std::uint8_t> bclump_, bfixed_;
  // Clump geometry per body (disks: n 1, s 0).
  std::vector<ClumpRest> brest_;  // particle count, rest shape and kept area
  std::vector<double> br_, bs_, bsdot_, blambda_, btarget_r_, btarget_s_, bux_, buy_;
  std::vector<double> next_r_, next_s_;  // set_cell_length_ratios' scratch
  std::vector<int> cell_body_;  // myocyte cell -> body, else -1

  // Particles (SoA, SI).
  std::vector<int> pbody_;
  std::vector<double> pa_;  // axial offset in spacings (k - (N-1)/2)
  std::vector<double> px_, py_, px_old_, py_old_, pvx_, pvy_, pr_, pw_;
  std::vector<int> body_particle_start_, body_particle_;  // each body's particles, ascending (CSR)
  std::vector<std::size_t> part_first_body_;              // the move loop's kStepParts parts of bodies
  std::vector<std::size_t> sum_part_first_body_;          // the force sums' parts (by contacts)
  std::vector<std::size_t> shape_part_first_body_;        // the clumps' shapes' parts (by clumps)
  std::vector<std::size_t> heavy_part_first_body_;        // under multirate: the heavy bodies' move parts
  std::vector<std::size_t> heavy_sum_part_first_body_;    // ... and their force sums' parts

  // Bonds, unbonded contacts (and the next list, scratch).
  BondSet bonds_, contacts_, next_contacts_;
  std::unique_ptr<ContactDetector> detector_;
  std::vector<std::pair<int, int>> candidate_pairs_;
  // Each contact's force on q (minus on p) and moments on its ends (moment[end],
  // end as in ContactIncidence's entries), numbered bonds then contacts; one
  // contact's in one cache line's half, as a particle's sum reads them.
  struct ContactForce {
    double fx, fy, moment[2];
  };
  std::vector<ContactForce> contact_force_;
  ContactIncidence particle_contacts_;

  // The longest DEM step [ms]: cells' lengths change over ms, and at the ~um/ms
  // speeds of contracting tissue a body moves less than the contact skin in it.
  static constexpr double kLongestStep_ms = 1.0;
  double stable_step_ms_ = 0;
  double bonded_stable_step_ms_ = 0;  // at the start (a loaded checkpoint's is checked against it)
  // Stable-step scratch: each contact's stiffness on its bodies (kr[2c + end]),
  // and each body's contacts.
  std::vector<double> contact_kt_, contact_kr_, body_kt_, body_kr_;
  ContactIncidence body_contacts_;
  double scaling_step_s_ = 0;  // mass scaling's target critical step H (0: none yet)
  std::size_t scaled_bodies_ = 0;
  double added_mass_fraction_ = 0, added_inertia_fraction_ = 0;
  // Multirate: light bodies (1; a heavy disk whose contacts make its
  // critical step shorter than the clumps' becomes light, never back) and their list; heavy bodies with a contact
  // to a light one (the boundary); the contacts touching a light body come
  // first in each set (fast_bonds_, fast_contacts_ of them); the light
  // bodies' stable step; each body's pose at the step's start (bx_start_,
  // by_start_, br_start_), and the heavy bodies' sums of the substeps' forces.
  std::vector<std::uint8_t> blight_;
  std::vector<int> light_bodies_, boundary_bodies_;
  std::vector<int> light_particle_;  // each light body's one particle (light bodies are disks)
  // The boundary's particles that touch a light body (placed each substep),
  // and each boundary body's fast contacts (CSR over boundary_bodies_:
  // ContactIncidence entries and the particle of each).
  std::vector<int> boundary_particles_, boundary_entry_start_, boundary_entry_, boundary_entry_particle_;
  std::vector<double> bx_start_, by_start_, br_start_, px_end_, py_end_;
  std::vector<double> fast_fx_, fast_fy_, fast_tq_;
  std::vector<std::pair<int, int>> candidate_scratch_;
  std::size_t fast_bonds_ = 0, fast_contacts_ = 0, substeps_ = 0;
  bool reclassify_pending_ = false;  // a heavy disk's critical step fell below the clumps
  double light_step_s_ = 0;
  double time_s_ = 0;
  std::size_t steps_ = 0;
  DemStrainFit strain_fit_;
  double origin_x_ = 0, origin_y_ = 0;  // for the strain sums' conditioning

  mutable std::vector<Particle> out_;
  mutable bool out_dirty_ = true;
};

}  // namespace fibrodem
