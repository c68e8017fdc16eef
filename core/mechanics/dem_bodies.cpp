// The DEM's bodies (dem_bodies.hpp): myocyte clumps and fibroblast disks
// built from the tissue, their particles, their parts, and what they tell.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_step_inline.hpp"
#include "mechanics/dem_units.hpp"

namespace fibrodem {

namespace {

// Every builder bonds the particles of coupled cells (the cell graph is
// derived from the bonds): couplings without bonds are a cell graph only.
void refuse_tissue_without_bonds(const Tissue& t) {
  if (!t.cell_edges.empty() && t.bonds.empty())
    throw std::invalid_argument("mechanics: the tissue's " + std::to_string(t.cell_edges.size()) +
                                " coupled cell pairs have no mechanical bonds; leave mechanics out of effects, or "
                                "use a builder that bonds cells");
}

}  // namespace

DemBodies::DemBodies(const Tissue& t, const DemSpec& spec)
    : area_rule(spec.area_rule), length_mode(spec.length_mode), local_damping(spec.local_damping) {
  refuse_tissue_without_bonds(t);
  add_bodies(t, spec);
  index_particles();
  partition_bodies();
}

// A body per fibroblast particle and per myocyte (the clump of its
// particles), in order of their first particle; then a disk per collagen
// particle (of no cell).
void DemBodies::add_bodies(const Tissue& t, const DemSpec& spec) {
  cells = t.cell_count();
  cell_particles = t.particles.size();
  const std::size_t np = t.particles.size() + t.collagen.size();
  const double rho = spec.density_kg_per_m3;  // x 1 m thickness
  cell_body.assign(cells, -1);
  pbody.assign(np, -1);
  pa.assign(np, 0.0);

  // Particles of each myocyte, in tissue order.
  std::vector<std::vector<int>> members(cells);
  for (std::size_t i = 0; i < cell_particles; ++i) {
    const int c = t.particles[i].cell;
    if (c < 0 || static_cast<std::size_t>(c) >= cells)
      throw std::invalid_argument("particle " + std::to_string(i) + " belongs to no cell");
    members[c].push_back(static_cast<int>(i));
  }

  auto add_body = [&](int c, bool clump, double x, double y, double theta, int n, double r0, double s0, double m,
                      double i, bool fixed) {
    bx.push_back(x);
    by.push_back(y);
    bth.push_back(theta);
    bcell.push_back(c);
    bclump.push_back(clump);
    bfixed.push_back(fixed);
    mass.push_back(m);
    inertia.push_back(i);
    density_mass.push_back(m);
    density_inertia.push_back(i);
    inv_m.push_back(fixed ? 0.0 : 1 / m);
    inv_i.push_back(fixed ? 0.0 : 1 / i);
    brest.push_back(clump_rest(spec.area_rule, n, r0, s0));
    br.push_back(r0);
    bs.push_back(s0);
    blambda.push_back(1.0);
    btarget_r.push_back(r0);
    btarget_s.push_back(s0);
    return static_cast<int>(bx.size()) - 1;
  };

  // One shape (all the paper's myocytes) -> mass properties computed once.
  struct ShapeProps {
    int n;
    double r, s, area, moment;
  };
  std::vector<ShapeProps> shapes;
  auto props = [&](int n, double r, double s) {
    for (const auto& p : shapes)
      if (p.n == n && std::abs(p.r - r) <= 1e-12 * r && std::abs(p.s - s) <= 1e-12 * std::max(s, r)) return p;
    shapes.push_back({n, r, s, union_area(n, r, s), union_polar_moment(n, r, s)});
    return shapes.back();
  };

  for (std::size_t i = 0; i < cell_particles; ++i) {
    const Particle& p = t.particles[i];
    const int c = p.cell;
    if (t.type[c] == CellType::fibroblast) {
      const double r = p.r_um * kUm;
      const double m = rho * M_PI * r * r;
      pbody[i] = add_body(c, false, p.x_um * kUm, p.y_um * kUm, 0.0, 1, r, 0.0, m, 0.5 * m * r * r,
                           spec.fibroblasts_fixed);
      continue;
    }
    if (cell_body[c] >= 0) continue;
    // A myocyte: the clump of all its particles.
    const auto& ids = members[c];
    const int n = static_cast<int>(ids.size());
    const std::string where = "myocyte cell " + std::to_string(c) + ": ";
    const double r0_um = t.particles[ids[0]].r_um;
    double cx = 0, cy = 0;
    for (int id : ids) {
      if (std::abs(t.particles[id].r_um - r0_um) > 1e-9 * r0_um)
        throw std::invalid_argument(where + "particles of different radii");
      cx += t.particles[id].x_um;
      cy += t.particles[id].y_um;
    }
    cx /= n;
    cy /= n;
    double ux = 0, uy = 1, s0_um = 0;
    if (n > 1) {
      const Particle &a = t.particles[ids.front()], &b = t.particles[ids.back()];
      const double len = std::hypot(b.x_um - a.x_um, b.y_um - a.y_um);
      if (!(len > 0)) throw std::invalid_argument(where + "particles at one point");
      ux = (b.x_um - a.x_um) / len;
      uy = (b.y_um - a.y_um) / len;
      double amin = 0, amax = 0;
      for (int id : ids) {
        const double dx = t.particles[id].x_um - cx, dy = t.particles[id].y_um - cy;
        const double along = dx * ux + dy * uy, across = dx * uy - dy * ux;
        if (std::abs(across) > 1e-6 * len) throw std::invalid_argument(where + "particles not collinear");
        amin = std::min(amin, along);
        amax = std::max(amax, along);
      }
      s0_um = (amax - amin) / (n - 1);
      for (int id : ids) {
        const double dx = t.particles[id].x_um - cx, dy = t.particles[id].y_um - cy;
        const double k = (dx * ux + dy * uy) / s0_um;
        const double k_round = std::round(k + 0.5 * (n - 1)) - 0.5 * (n - 1);
        if (std::abs(k - k_round) > 1e-6) throw std::invalid_argument(where + "particles not equally spaced");
        pa[id] = k_round;
      }
    }
    const double r0 = r0_um * kUm, s0 = s0_um * kUm;
    const ShapeProps sp = props(n, r0, s0);
    const int b = add_body(c, true, cx * kUm, cy * kUm, std::atan2(-ux, uy), n, r0, s0, rho * sp.area,
                           rho * sp.moment, false);
    cell_body[c] = b;
    for (int id : ids) pbody[id] = b;
  }
  for (std::size_t k = 0; k < t.collagen.size(); ++k) {
    const Particle& p = t.collagen[k];
    const double r = p.r_um * kUm;
    const double m = rho * M_PI * r * r;
    pbody[cell_particles + k] = add_body(-1, false, p.x_um * kUm, p.y_um * kUm, 0.0, 1, r, 0.0, m, 0.5 * m * r * r, false);
  }
}

// The bodies at rest, their particles placed (each body's particles listed,
// CSR), and the particles' centre (the origin of the strain sums).
void DemBodies::index_particles() {
  const std::size_t nb = bx.size(), np = pbody.size();
  bvx.assign(nb, 0.0);
  bvy.assign(nb, 0.0);
  bw.assign(nb, 0.0);
  bfx.assign(nb, 0.0);
  bfy.assign(nb, 0.0);
  btq.assign(nb, 0.0);
  bsdot.assign(nb, 0.0);
  bux.resize(nb);
  buy.resize(nb);
  next_r.resize(nb);
  next_s.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    bux[b] = -std::sin(bth[b]);
    buy[b] = std::cos(bth[b]);
  }
  for (auto* v : {&px, &py, &px_old, &py_old, &pvx, &pvy, &pr, &pw}) v->assign(np, 0.0);
  body_particle_start.assign(nb + 1, 0);
  for (std::size_t i = 0; i < np; ++i) ++body_particle_start[pbody[i] + 1];
  for (std::size_t b = 0; b < nb; ++b) body_particle_start[b + 1] += body_particle_start[b];
  body_particle.resize(np);
  {
    std::vector<int> fill(body_particle_start.begin(), body_particle_start.end() - 1);
    for (std::size_t i = 0; i < np; ++i) body_particle[fill[pbody[i]]++] = static_cast<int>(i);
  }
  for (std::size_t b = 0; b < nb; ++b) place_particles_of(b);
  for (std::size_t i = 0; i < np; ++i) {
    origin_x += px[i] / static_cast<double>(np);
    origin_y += py[i] / static_cast<double>(np);
  }
}

// `parts` runs of whole bodies of about equal work, from each body's work
// summed before it (work_before[b]: bodies [0, b)): each part's first body,
// and the body count last.
std::vector<std::size_t> parts_of_equal_work(const std::vector<double>& work_before, std::size_t parts) {
  const std::size_t nb = work_before.size() - 1;
  std::vector<std::size_t> first(parts + 1);
  for (std::size_t k = 0; k < parts; ++k)
    first[k] = static_cast<std::size_t>(std::lower_bound(work_before.begin(), work_before.end() - 1,
                                                         work_before[nb] * static_cast<double>(k) / parts) -
                                        work_before.begin());
  first[parts] = nb;
  return first;
}

// The step's fixed parts: runs of whole bodies of about equal work, so that
// the threads, which take equal numbers of parts, finish the move loop
// together. A body's work there: its kick, drift and fits (2.2 particles'
// worth) and its particles' placing, from thread CPU times on the Fig. 3
// interstitial tissue. (Parts of equal particle counts put all its
// myocytes, which it lists first, on one thread, and its 4915 fibroblast
// disks with a third of the myocytes on the other: 1.7x the first's work.)
// The clumps' shapes (set_cell_length_ratios) have parts of equal clump
// counts: a disk there is passed over.
void DemBodies::partition_bodies() {
  part_first_body = parts_of_bodies(bx.size(), kStepParts, [&](std::size_t b) { return move_work(b); });
  constexpr double kShapeWork = 1.0, kDiskPassWork = 0.02;
  shape_part_first_body =
      parts_of_bodies(bx.size(), kStepParts, [&](std::size_t b) {
        return !steps(b) ? 0.0 : bclump[b] ? kShapeWork : kDiskPassWork;
      });
}

// The force sums' parts: runs of whole bodies of about equal work there,
// which goes with the contacts a body's particles sum (a myocyte's particles
// touch ~4 neighbours each, an interstitial fibroblast's disk a handful in
// all), not with the move loop's particle counts. Each body's sum is its own,
// in a fixed order, so the parts change no bits; they are set again whenever
// the contacts change.
void DemBodies::partition_force_sums(const ContactIncidence& particle_contacts) {
  sum_part_first_body =
      parts_of_bodies(bx.size(), kStepParts, [&](std::size_t b) { return sum_work(b, particle_contacts); });
}

double DemBodies::move_work(std::size_t b) const {
  if (!steps(b)) return 0;
  constexpr double kBodyWork = 2.2;
  return kBodyWork + (body_particle_start[b + 1] - body_particle_start[b]);
}

double DemBodies::sum_work(std::size_t b, const ContactIncidence& particle_contacts) const {
  if (!steps(b)) return 0;
  double work = 2.0;  // the kick and the body's own sums, in contact-terms
  for (int k = body_particle_start[b]; k < body_particle_start[b + 1]; ++k) {
    const auto i = static_cast<std::size_t>(body_particle[k]);
    work += 1.0 + static_cast<double>(particle_contacts.end(i) - particle_contacts.begin(i));
  }
  return work;
}

void DemBodies::export_particles(std::vector<Particle>& out) const {
  out.resize(cell_particles);  // (the cells' particles: collagen is in no picture)
  for (std::size_t i = 0; i < cell_particles; ++i) {
    const int b = pbody[i];
    out[i] = Particle{px[i] / kUm, py[i] / kUm, br[b] / kUm, bcell[b]};
  }
}

ClumpShape DemBodies::cell_shape_um(int cell) const {
  const int b = cell_body.at(cell);
  if (b < 0) return {0, 0};
  return {br[b] / kUm, bs[b] / kUm};
}

double DemBodies::kinetic_energy_J() const {
  double e = 0;
  for (std::size_t b = 0; b < bx.size(); ++b)
    e += 0.5 * mass[b] * (bvx[b] * bvx[b] + bvy[b] * bvy[b]) + 0.5 * inertia[b] * bw[b] * bw[b];
  return e;
}

// Reach of a body: its farthest particle's edge from its centroid (a
// clump's end pebbles; a disk's radius), at its present shape.
MechanicsSolver::Motion DemBodies::fastest_motion() const {
  MechanicsSolver::Motion m;
  for (std::size_t b = 0; b < bx.size(); ++b) {
    if (bfixed[b] || !steps(b)) continue;
    const double reach = 0.5 * (brest[b].n - 1) * bs[b] + br[b];
    const double speed = std::hypot(bvx[b], bvy[b]) + std::abs(bw[b]) * reach;
    const double accel = std::hypot(bfx[b], bfy[b]) * inv_m[b] + std::abs(btq[b]) * inv_i[b] * reach;
    m.speed_m_per_s = std::max(m.speed_m_per_s, speed);
    m.acceleration_m_per_s2 = std::max(m.acceleration_m_per_s2, accel);
  }
  return m;
}

}  // namespace fibrodem
