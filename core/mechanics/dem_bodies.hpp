// The DEM's bodies and their particles (dem_solver.hpp, "Bodies"): a body
// per myocyte (the rigid clump of its collinear particles) and per
// fibroblast particle (a disk), in order of their first particle, then a
// disk per collagen particle (of no cell: bcell -1); their
// state in structure-of-arrays (SI), each body's particles (CSR), and the
// fixed parts of bodies the step's loops take (dem_solver.hpp, "Threads").
// The per-body pieces of a step (kick, drift_and_reshape,
// place_particles_of) are defined in dem_step_inline.hpp, for the step's
// loops to inline.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "mechanics/clump_geometry.hpp"
#include "mechanics/contact_incidence.hpp"
#include "mechanics/dem_spec.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Runs of whole bodies [0, nb) of about equal work(b) each: each of the
// `parts` runs' first body, and nb last.
std::vector<std::size_t> parts_of_equal_work(const std::vector<double>& work_before, std::size_t parts);
template <class Work>
std::vector<std::size_t> parts_of_bodies(std::size_t nb, std::size_t parts, Work work) {
  std::vector<double> work_before(nb + 1, 0.0);  // work of bodies [0, b)
  for (std::size_t b = 0; b < nb; ++b) work_before[b + 1] = work_before[b] + work(b);
  return parts_of_equal_work(work_before, parts);
}

// The critical step of a body of mass m, inertia i on stiffnesses kt, kr
// (infinite without contacts).
inline double critical_step_s(double m, double i, double kt, double kr) {
  double t = std::numeric_limits<double>::infinity();
  if (kt > 0) t = std::min(t, std::sqrt(m / kt));
  if (kr > 0) t = std::min(t, std::sqrt(i / kr));
  return t;
}

class DemBodies {
 public:
  // The step's loops' parts of bodies: fixed by the tissue, not the threads.
  static constexpr std::size_t kStepParts = 64;

  // Throws std::invalid_argument for a myocyte whose particles are not
  // collinear, equally spaced and of one radius, and for a tissue whose
  // coupled cells have no bonds.
  DemBodies(const Tissue& tissue, const DemSpec& spec);

  std::size_t size() const { return bx.size(); }
  std::size_t particle_count() const { return px.size(); }

  // Velocity Verlet's pieces for body b (dem_step_inline.hpp): the half
  // kick of h_s with PFC's local damping; the drift over dt_s and the
  // clump's shape at its target; its particles placed.
  void kick(std::size_t b, double h_s);
  void drift_and_reshape(std::size_t b, double dt_s);
  void place_particles_of(std::size_t b);

  // Each myocyte's target shape at its length ratio (dem_reshape.cpp); throws
  // std::invalid_argument, changing nothing, as MechanicsSolver's does.
  void set_cell_length_ratios(const std::vector<double>& ratio);
  // The force sums' parts, by each body's contacts (set again whenever the
  // contacts change).
  void partition_force_sums(const ContactIncidence& particle_contacts);
  // The move loop's and the shapes' parts (again once `own` is set).
  void partition_bodies();
  // A body's work in the move loop and in the force sums (the parts' weights;
  // 0 for a body another rank steps).
  double move_work(std::size_t b) const;
  double sum_work(std::size_t b, const ContactIncidence& particle_contacts) const;

  MechanicsSolver::Motion fastest_motion() const;
  double kinetic_energy_J() const;
  // The cells' particles [um], in the tissue's order (not the collagen's).
  void export_particles(std::vector<Particle>& out) const;
  // A myocyte's present pebble radius and spacing [um]; {0, 0} for a fibroblast.
  ClumpShape cell_shape_um(int cell) const;

  std::size_t cells = 0;
  std::size_t cell_particles = 0;  // the cells' particles, before the collagen's
  AreaRule area_rule;
  LengthMode length_mode;
  double local_damping = 0;  // PFC's alpha (spec local_damping)

  // Bodies: pose, velocity, force.
  std::vector<double> bx, by, bth, bvx, bvy, bw, bfx, bfy, btq;
  // Masses and inertias of motion (mass scaling may have raised them), and
  // those of the bodies' density (the dashpots').
  std::vector<double> inv_m, inv_i, mass, inertia, density_mass, density_inertia;
  std::vector<int> bcell;
  std::vector<std::uint8_t> bclump, bfixed;
  // Clump geometry per body (disks: n 1, s 0): rest shape, radius, spacing
  // and its rate, length ratio, target shape, axis.
  std::vector<ClumpRest> brest;  // particle count, rest shape and kept area
  std::vector<double> br, bs, bsdot, blambda, btarget_r, btarget_s, bux, buy;
  std::vector<double> next_r, next_s;  // set_cell_length_ratios' scratch
  std::vector<int> cell_body;          // myocyte cell -> body, else -1

  // Particles: body, axial offset in spacings (k - (N-1)/2), place now and a
  // step ago, velocity, radius, spin.
  std::vector<int> pbody;
  std::vector<double> pa;
  std::vector<double> px, py, px_old, py_old, pvx, pvy, pr, pw;
  std::vector<int> body_particle_start, body_particle;  // each body's particles, ascending (CSR)
  double origin_x = 0, origin_y = 0;  // the particles' centre at rest (the fits' origin)

  // Split over ranks (dem_split.hpp): 1 for each body this rank steps;
  // empty in one process, which steps every body.
  std::vector<std::uint8_t> own;
  bool steps(std::size_t b) const { return own.empty() || own[b] != 0; }

  std::vector<std::size_t> part_first_body;        // the move loop's kStepParts parts of bodies
  std::vector<std::size_t> sum_part_first_body;    // the force sums' parts (by contacts)
  std::vector<std::size_t> shape_part_first_body;  // the clumps' shapes' parts (by clumps)

 private:
  void add_bodies(const Tissue& tissue, const DemSpec& spec);
  void index_particles();
};

// Each array of the bodies' evolving state, with its checkpoint field's
// name (Bodies: DemBodies or const DemBodies): pose, velocity, force, and
// the clump's shape on its way to the target.
template <class Bodies, class F>
void for_each_evolving_body_array(Bodies& b, F&& f) {
  f("dem.body.x", b.bx), f("dem.body.y", b.by), f("dem.body.theta", b.bth);
  f("dem.body.vx", b.bvx), f("dem.body.vy", b.bvy), f("dem.body.omega", b.bw);
  f("dem.body.fx", b.bfx), f("dem.body.fy", b.bfy), f("dem.body.torque", b.btq);
  f("dem.body.r", b.br), f("dem.body.s", b.bs), f("dem.body.sdot", b.bsdot), f("dem.body.lambda", b.blambda);
  f("dem.body.target_r", b.btarget_r), f("dem.body.target_s", b.btarget_s), f("dem.body.ux", b.bux);
  f("dem.body.uy", b.buy);
}
inline constexpr std::size_t kEvolvingBodyArrays = 17;

}  // namespace fibrodem
