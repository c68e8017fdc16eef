// The DEM's bodies (dem_solver.hpp, "Bodies"): myocyte clumps and fibroblast
// disks built from the tissue, their particles, and what they tell.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mechanics/dem_solver.hpp"
#include "mechanics/dem_step_inline.hpp"
#include "mechanics/dem_units.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

DemSolver::DemSolver(const Tissue& t, const DemSpec& spec) : spec_(spec), law_(make_contact_law(spec)) {
  add_bodies(t);
  index_particles();
  partition_bodies();
  const std::vector<std::pair<int, int>> bonded = form_bonds(t);
  law_->prepare(bonds_);
  if (spec_.contact_detection) {
    detector_ = std::make_unique<ContactDetector>(pbody_, bonded, spec_.contact_skin_um * kUm);
    rebuild_contacts();
  } else {
    index_contacts();
    compute_stable_step();
  }
  if (spec_.multirate) start_multirate();
  bonded_stable_step_ms_ = stable_step_ms_;
  if (spec_.dt_ms > stable_step_ms_)
    throw std::invalid_argument("mechanics.dt_ms " + significant_digits(spec_.dt_ms, 6) + " ms exceeds the stable DEM step " +
                                significant_digits(stable_step_ms_, 6) + " ms");
}

// A body per fibroblast particle and per myocyte (the clump of its
// particles), in order of their first particle.
void DemSolver::add_bodies(const Tissue& t) {
  cells_ = t.cell_count();
  const std::size_t np = t.particles.size();
  // Every builder that makes a mechanical body bonds the particles of coupled
  // cells; a tissue with couplings and no bonds is a cell graph only (fibrotic_sheet).
  if (!t.cell_edges.empty() && t.bonds.empty())
    throw std::invalid_argument("mechanics: the tissue's " + std::to_string(t.cell_edges.size()) +
                                " coupled cell pairs have no mechanical bonds (builder fibrotic_sheet makes the "
                                "cell graph only); leave mechanics out of effects, or use a builder that bonds cells");
  const double rho = spec_.density_kg_per_m3;  // x 1 m thickness
  cell_body_.assign(cells_, -1);
  pbody_.assign(np, -1);
  pa_.assign(np, 0.0);

  // Particles of each myocyte, in tissue order.
  std::vector<std::vector<int>> members(cells_);
  for (std::size_t i = 0; i < np; ++i) {
    const int c = t.particles[i].cell;
    if (c < 0 || static_cast<std::size_t>(c) >= cells_)
      throw std::invalid_argument("particle " + std::to_string(i) + " belongs to no cell");
    members[c].push_back(static_cast<int>(i));
  }

  auto add_body = [&](int cell, bool clump, double x, double y, double theta, int n, double r0,
                      double s0, double mass, double inertia, bool fixed) {
    bx_.push_back(x);
    by_.push_back(y);
    bth_.push_back(theta);
    bcell_.push_back(cell);
    bclump_.push_back(clump);
    bfixed_.push_back(fixed);
    mass_.push_back(mass);
    inertia_.push_back(inertia);
    density_mass_.push_back(mass);
    density_inertia_.push_back(inertia);
    inv_m_.push_back(fixed ? 0.0 : 1 / mass);
    inv_i_.push_back(fixed ? 0.0 : 1 / inertia);
    brest_.push_back(clump_rest(spec_.area_rule, n, r0, s0));
    br_.push_back(r0);
    bs_.push_back(s0);
    blambda_.push_back(1.0);
    btarget_r_.push_back(r0);
    btarget_s_.push_back(s0);
    return static_cast<int>(bx_.size()) - 1;
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

  for (std::size_t i = 0; i < np; ++i) {
    const Particle& p = t.particles[i];
    const int c = p.cell;
    if (t.type[c] == CellType::fibroblast) {
      const double r = p.r_um * kUm;
      const double m = rho * M_PI * r * r;
      pbody_[i] = add_body(c, false, p.x_um * kUm, p.y_um * kUm, 0.0, 1, r, 0.0, m, 0.5 * m * r * r,
                           spec_.fibroblasts_fixed);
      continue;
    }
    if (cell_body_[c] >= 0) continue;
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
        pa_[id] = k_round;
      }
    }
    const double r0 = r0_um * kUm, s0 = s0_um * kUm;
    const ShapeProps sp = props(n, r0, s0);
    const int b = add_body(c, true, cx * kUm, cy * kUm, std::atan2(-ux, uy), n, r0, s0, rho * sp.area,
                           rho * sp.moment, false);
    cell_body_[c] = b;
    for (int id : ids) pbody_[id] = b;
  }
}

// The bodies at rest, their particles placed (each body's particles listed,
// CSR), and the particles' centre (the origin of the strain sums).
void DemSolver::index_particles() {
  const std::size_t nb = bx_.size(), np = pbody_.size();
  bvx_.assign(nb, 0.0);
  bvy_.assign(nb, 0.0);
  bw_.assign(nb, 0.0);
  bfx_.assign(nb, 0.0);
  bfy_.assign(nb, 0.0);
  btq_.assign(nb, 0.0);
  bsdot_.assign(nb, 0.0);
  bux_.resize(nb);
  buy_.resize(nb);
  next_r_.resize(nb);
  next_s_.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    bux_[b] = -std::sin(bth_[b]);
    buy_[b] = std::cos(bth_[b]);
  }
  for (auto* v : {&px_, &py_, &px_old_, &py_old_, &pvx_, &pvy_, &pr_, &pw_}) v->assign(np, 0.0);
  body_particle_start_.assign(nb + 1, 0);
  for (std::size_t i = 0; i < np; ++i) ++body_particle_start_[pbody_[i] + 1];
  for (std::size_t b = 0; b < nb; ++b) body_particle_start_[b + 1] += body_particle_start_[b];
  body_particle_.resize(np);
  {
    std::vector<int> fill(body_particle_start_.begin(), body_particle_start_.end() - 1);
    for (std::size_t i = 0; i < np; ++i) body_particle_[fill[pbody_[i]]++] = static_cast<int>(i);
  }
  for (std::size_t b = 0; b < nb; ++b) place_particles_of(b);
  for (std::size_t i = 0; i < np; ++i) {
    origin_x_ += px_[i] / static_cast<double>(np);
    origin_y_ += py_[i] / static_cast<double>(np);
  }
}

namespace {

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

// `parts` runs of whole bodies [0, nb) of about equal work(b) each.
template <class Work>
std::vector<std::size_t> parts_of_bodies(std::size_t nb, std::size_t parts, Work work) {
  std::vector<double> work_before(nb + 1, 0.0);  // work of bodies [0, b)
  for (std::size_t b = 0; b < nb; ++b) work_before[b + 1] = work_before[b] + work(b);
  return parts_of_equal_work(work_before, parts);
}

}  // namespace

// The step's fixed parts: runs of whole bodies of about equal work, so that
// the threads, which take equal numbers of parts, finish the move loop
// together. A body's work there: its kick, drift and fits (2.2 particles'
// worth) and its particles' placing, from thread CPU times on the Fig. 3
// interstitial tissue. (Parts of equal particle counts put all its
// myocytes, which it lists first, on one thread, and its 4915 fibroblast
// disks with a third of the myocytes on the other: 1.7x the first's work.)
// The clumps' shapes (set_cell_length_ratios) have parts of equal clump
// counts: a disk there is passed over.
void DemSolver::partition_bodies() {
  part_first_body_ = parts_of_bodies(bx_.size(), kStepParts, [&](std::size_t b) { return move_work(b); });
  constexpr double kShapeWork = 1.0, kDiskPassWork = 0.02;
  shape_part_first_body_ = parts_of_bodies(bx_.size(), kStepParts,
                                           [&](std::size_t b) { return bclump_[b] ? kShapeWork : kDiskPassWork; });
}

// The force sums' parts: runs of whole bodies of about equal work there,
// which goes with the contacts a body's particles sum (a myocyte's particles
// touch ~4 neighbours each, an interstitial fibroblast's disk a handful in
// all), not with the move loop's particle counts. Each body's sum is its own,
// in a fixed order, so the parts change no bits; they are set again whenever
// the contacts change.
void DemSolver::partition_force_sums() {
  sum_part_first_body_ = parts_of_bodies(bx_.size(), kStepParts, [&](std::size_t b) { return sum_work(b); });
  partition_heavy_bodies();
}

// Under multirate, the parts of the loops over the heavy bodies alone
// (move_heavy_bodies, heavy_forces_and_kick): a light body there only has
// its pose copied or is passed over. The interstitial tissue lists its
// myocytes (heavy) first, so the parts of the whole step put nearly all of
// that work on one thread. Set again when the contacts or the light set change.
void DemSolver::partition_heavy_bodies() {
  if (blight_.empty()) return;
  constexpr double kPoseCopyWork = 0.2, kPassWork = 0.1;
  heavy_part_first_body_ =
      parts_of_bodies(bx_.size(), kStepParts, [&](std::size_t b) { return blight_[b] ? kPoseCopyWork : move_work(b); });
  heavy_sum_part_first_body_ =
      parts_of_bodies(bx_.size(), kStepParts, [&](std::size_t b) { return blight_[b] ? kPassWork : sum_work(b); });
}

double DemSolver::move_work(std::size_t b) const {
  constexpr double kBodyWork = 2.2;
  return kBodyWork + (body_particle_start_[b + 1] - body_particle_start_[b]);
}

double DemSolver::sum_work(std::size_t b) const {
  double work = 2.0;  // the kick and the body's own sums, in contact-terms
  for (int k = body_particle_start_[b]; k < body_particle_start_[b + 1]; ++k) {
    const auto i = static_cast<std::size_t>(body_particle_[k]);
    work += 1.0 + static_cast<double>(particle_contacts_.end(i) - particle_contacts_.begin(i));
  }
  return work;
}

const std::vector<Particle>& DemSolver::particles() const {
  if (out_dirty_) {
    out_.resize(pbody_.size());
    for (std::size_t i = 0; i < pbody_.size(); ++i) {
      const int b = pbody_[i];
      out_[i] = Particle{px_[i] / kUm, py_[i] / kUm, br_[b] / kUm, bcell_[b]};
    }
    out_dirty_ = false;
  }
  return out_;
}

DemSolver::BodyState DemSolver::body(std::size_t b) const {
  return {bx_[b], by_[b], bth_[b], bvx_[b], bvy_[b], bw_[b], mass_[b], inertia_[b],
          bcell_[b], bclump_[b] != 0, bfixed_[b] != 0};
}

void DemSolver::set_body_velocity(std::size_t b, double vx, double vy, double w) {
  if (bfixed_[b]) return;
  bvx_[b] = vx;
  bvy_[b] = vy;
  bw_[b] = w;
}

ClumpShape DemSolver::cell_shape_um(int cell) const {
  const int b = cell_body_.at(cell);
  if (b < 0) return {0, 0};
  return {br_[b] / kUm, bs_[b] / kUm};
}

double DemSolver::kinetic_energy_J() const {
  double e = 0;
  for (std::size_t b = 0; b < bx_.size(); ++b)
    e += 0.5 * mass_[b] * (bvx_[b] * bvx_[b] + bvy_[b] * bvy_[b]) + 0.5 * inertia_[b] * bw_[b] * bw_[b];
  return e;
}

}  // namespace fibrodem
