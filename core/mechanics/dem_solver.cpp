#include "mechanics/dem_solver.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace fibrodem {
namespace {

constexpr double kUm = 1e-6;  // m per um
// The longest DEM step [ms]: cells' lengths change over ms, and at the ~um/ms
// speeds of contracting tissue a body moves less than the contact skin in it.
constexpr double kLongestStep_ms = 1.0;

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

}  // namespace

DemSolver::DemSolver(const Tissue& t, const DemSpec& spec) : spec_(spec), law_(make_contact_law(spec)) {
  cells_ = t.cell_count();
  const std::size_t np = t.particles.size();
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

  const std::size_t nb = bx_.size();
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
  // The step's fixed parts: runs of whole bodies with about np / kStepParts particles.
  part_first_body_.resize(kStepParts + 1);
  for (std::size_t k = 0; k <= kStepParts; ++k)
    part_first_body_[k] = static_cast<std::size_t>(
        std::lower_bound(body_particle_start_.begin(), body_particle_start_.end() - 1,
                         static_cast<int>(np * k / kStepParts)) -
        body_particle_start_.begin());
  for (std::size_t i = 0; i < np; ++i) {
    origin_x_ += px_[i] / static_cast<double>(np);
    origin_y_ += py_[i] / static_cast<double>(np);
  }

  // Bonds: formed at the start, unloaded (reference gap = the gap now).
  bonds_.resize(t.bonds.size());
  std::vector<std::pair<int, int>> bonded(t.bonds.size());
  for (std::size_t k = 0; k < t.bonds.size(); ++k) {
    const int p = t.bonds[k].p, q = t.bonds[k].q;
    if (p < 0 || q < 0 || static_cast<std::size_t>(p) >= np || static_cast<std::size_t>(q) >= np || p == q)
      throw std::invalid_argument("bond " + std::to_string(k) + " joins invalid particles");
    if (pbody_[p] == pbody_[q])
      throw std::invalid_argument("bond " + std::to_string(k) + " joins two particles of one clump");
    set_contact_constants(bonds_, k, p, q);
    bonds_.ref_gap[k] = std::hypot(px_[q] - px_[p], py_[q] - py_[p]) - br_[pbody_[p]] - br_[pbody_[q]];
    bonds_.kb[k] = law_->bending_stiffness(bonds_.kn[k], br_[pbody_[p]], br_[pbody_[q]]);
    bonds_.intact[k] = 1;
    bonded[k] = {p, q};
  }
  law_->prepare(bonds_);
  if (spec_.contact_detection) {
    detector_ = std::make_unique<ContactDetector>(pbody_, bonded, spec_.contact_skin_um * kUm);
    rebuild_contacts();
  } else {
    index_contacts();
    compute_stable_step();
  }
  bonded_stable_step_ms_ = stable_step_ms_;
  if (spec_.dt_ms > stable_step_ms_)
    throw std::invalid_argument("mechanics.dt_ms " + fmt(spec_.dt_ms) + " ms exceeds the stable DEM step " +
                                fmt(stable_step_ms_) + " ms");
}

// Stiffness by inheritance and cell types, effective mass of the two bodies (a
// fixed body's partner alone); state zeroed, reference gap 0 and no bending
// (a contact).
void DemSolver::set_contact_constants(BondSet& set, std::size_t k, int p, int q) const {
  const double series = spec_.stiffness_inheritance == StiffnessInheritance::series ? 0.5 : 1.0;
  const int bp = pbody_[p], bq = pbody_[q];
  const bool fib = !bclump_[bp] || !bclump_[bq];
  const double factor = series * (fib ? spec_.fibroblast_stiffness_factor : 1.0);
  set.p[k] = p;
  set.q[k] = q;
  set.kn[k] = spec_.kn_N_per_m * factor;
  set.ks[k] = spec_.ks_N_per_m * factor;
  const double mp = mass_[bp], mq = mass_[bq];
  set.m_eff[k] = bfixed_[bp] && !bfixed_[bq]   ? mq
                 : bfixed_[bq] && !bfixed_[bp] ? mp
                                               : mp * mq / (mp + mq);
  set.ref_gap[k] = 0;
  set.kb[k] = 0;
  set.fn[k] = 0;
  set.fs[k] = 0;
  set.mb[k] = 0;
  set.intact[k] = 0;
}

// A new Verlet list of unbonded contacts; a pair on the old list keeps its
// shear force (both lists ascending, merged); the stable step follows.
void DemSolver::rebuild_contacts() {
  detector_->build(px_.data(), py_.data(), pr_.data(), candidate_pairs_);
  const std::size_t n = candidate_pairs_.size();
  next_contacts_.resize(n);
  std::size_t old = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto [p, q] = candidate_pairs_[k];
    set_contact_constants(next_contacts_, k, p, q);
    while (old < contacts_.size() && std::make_pair(contacts_.p[old], contacts_.q[old]) < candidate_pairs_[k]) ++old;
    if (old < contacts_.size() && contacts_.p[old] == p && contacts_.q[old] == q) {
      next_contacts_.fn[k] = contacts_.fn[old];
      next_contacts_.fs[k] = contacts_.fs[old];
    }
  }
  law_->prepare(next_contacts_);
  std::swap(contacts_, next_contacts_);
  index_contacts();
  compute_stable_step();
  if (spec_.dt_ms > stable_step_ms_ && steps_ > 0)
    throw std::invalid_argument("at t = " + fmt(time_ms()) + " ms new contacts lower the stable DEM step to " +
                                fmt(stable_step_ms_) + " ms, below mechanics.dt_ms " + fmt(spec_.dt_ms) +
                                " ms: lower mechanics.dt_ms, or leave it out (automatic step)");
}

// Each contact's stiffness on its two bodies (in parallel), summed per body
// in contact order (body_contacts_), then the smallest critical step.
void DemSolver::compute_stable_step() {
  const std::size_t nbonds = bonds_.size(), n = nbonds + contacts_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < n; ++c) {
    const BondSet& set = c < nbonds ? bonds_ : contacts_;
    const std::size_t k = c < nbonds ? c : c - nbonds;
    const int p = set.p[k], q = set.q[k];
    const double kn = law_->stable_step_stiffness(set.kn[k], false);
    const double ks = law_->stable_step_stiffness(set.ks[k], true);
    const double dx = px_[q] - px_[p], dy = py_[q] - py_[p];
    const double d = std::hypot(dx, dy);
    const double nx = d > 0 ? dx / d : 1.0, ny = d > 0 ? dy / d : 0.0;
    const int bp = pbody_[p], bq = pbody_[q];
    const double gap = d - br_[bp] - br_[bq];
    const double cx = px_[p] + (br_[bp] + 0.5 * gap) * nx, cy = py_[p] + (br_[bp] + 0.5 * gap) * ny;
    contact_kt_[c] = kn + ks;
    for (int end : {0, 1}) {
      const int b = end ? bq : bp;
      const double rx = cx - bx_[b], ry = cy - by_[b];
      const double rn = rx * ny - ry * nx;    // rho x n
      const double rt = rx * nx + ry * ny;    // rho x t, t = (-ny, nx)
      contact_kr_[2 * c + end] = kn * rn * rn + ks * rt * rt + set.kb[k];
    }
  }
  double tmin = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(min : tmin)
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    if (bfixed_[b]) continue;
    double kt = 0, kr = 0;
    for (const int* e = body_contacts_.begin(b); e != body_contacts_.end(b); ++e) {
      kt += contact_kt_[ContactIncidence::contact(*e)];
      kr += contact_kr_[*e];
    }
    if (kt > 0) tmin = std::min(tmin, std::sqrt(mass_[b] / kt));
    if (kr > 0) tmin = std::min(tmin, std::sqrt(inertia_[b] / kr));
  }
  // Bodies without contacts have no stiffness limit: cap the step (PFC also
  // bounds it kinematically), so that a lone contracting clump still moves and
  // free bodies cannot cross a contact skin between two checks of the list.
  stable_step_ms_ = std::min(spec_.safety_factor * tmin * 1e3, kLongestStep_ms);
}

void DemSolver::set_cell_length_ratios(const std::vector<double>& ratio) {
  if (ratio.size() != cells_)
    throw std::invalid_argument("set_cell_length_ratios: " + std::to_string(ratio.size()) +
                                " ratios for " + std::to_string(cells_) + " cells");
  // Each myocyte's new shape (cells are independent: in parallel), kept only
  // if every ratio is in range and every shape exists; else the error of the
  // first cell that fails, and nothing changed. Each thread takes the step's
  // fixed parts of bodies, as move_bodies and the force sums do, so that a
  // body's data stay in one core's cache from step to step. (Shared in chunks
  // of 64 cells as the threads came free, they moved between the cores: in
  // Fig. 3 EM on two threads the shapes took 162 us a DEM step, now 138.)
  const std::size_t none = cells_;
  std::size_t failed = none;
  std::string error;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = part_first_body_[k]; b < part_first_body_[k + 1]; ++b) {
        if (!bclump_[b]) continue;  // a fibroblast keeps its disk
        const auto c = static_cast<std::size_t>(bcell_[b]);
        const double l = ratio[c];
        if (!(l >= 0.5 && l <= 1.5)) {
#pragma omp critical(dem_shape_error)
          if (c < failed) {
            failed = c;
            error = "cell " + std::to_string(c) + ": length ratio " + fmt(l) + " outside [0.5, 1.5]";
          }
          continue;
        }
        if (brest_[b].n < 2) continue;
        next_r_[b] = btarget_r_[b];
        next_s_[b] = btarget_s_[b];
        if (l == blambda_[b]) continue;
        try {
          const ClumpShape shape = contracted_shape(spec_.area_rule, spec_.length_mode, brest_[b], l,
                                                    btarget_r_[b]);
          next_r_[b] = shape.r;
          next_s_[b] = shape.s;
        } catch (const std::invalid_argument& e) {
#pragma omp critical(dem_shape_error)
          if (c < failed) {
            failed = c;
            error = e.what();
          }
        }
      }
    // (After the loop's barrier every thread reads the same `failed`.)
    if (failed == none) {
#pragma omp for schedule(static) nowait
      for (std::size_t k = 0; k < kStepParts; ++k)
        for (std::size_t b = part_first_body_[k]; b < part_first_body_[k + 1]; ++b) {
          if (!bclump_[b] || brest_[b].n < 2) continue;
          blambda_[b] = ratio[static_cast<std::size_t>(bcell_[b])];
          btarget_r_[b] = next_r_[b];
          btarget_s_[b] = next_s_[b];
        }
    }
  }
  if (failed != none) throw std::invalid_argument(error);
}

// (The per-body helpers below are forced inline: GCC 12 kept them as calls,
// one per body or particle.)

// v += (F - alpha |F| sign(v)) / m * h for each degree of freedom (PFC's
// local damping; alpha 0: plain Newton).
[[gnu::always_inline]] inline void DemSolver::kick_body(std::size_t b, double h_s) {
  if (bfixed_[b]) return;
  const double alpha = spec_.local_damping;
  auto damped = [alpha](double f, double v) {
    return v > 0 ? f - alpha * std::abs(f) : v < 0 ? f + alpha * std::abs(f) : f;
  };
  bvx_[b] += damped(bfx_[b], bvx_[b]) * inv_m_[b] * h_s;
  bvy_[b] += damped(bfy_[b], bvy_[b]) * inv_m_[b] * h_s;
  bw_[b] += damped(btq_[b], bw_[b]) * inv_i_[b] * h_s;
}

// Drift at the half-step velocity, then the clump's shape at the length ratio
// set for the step's end (its spacing's rate for the pebbles' slide) and its axis.
[[gnu::always_inline]] inline void DemSolver::drift_and_reshape(std::size_t b, double dt_s) {
  if (!bfixed_[b]) {
    bx_[b] += bvx_[b] * dt_s;
    by_[b] += bvy_[b] * dt_s;
    bth_[b] += bw_[b] * dt_s;
  }
  bsdot_[b] = 0;
  if (btarget_s_[b] != bs_[b] || btarget_r_[b] != br_[b]) {
    bsdot_[b] = (btarget_s_[b] - bs_[b]) / dt_s;
    bs_[b] = btarget_s_[b];
    br_[b] = btarget_r_[b];
  }
  if (brest_[b].n < 2) return;  // a disk has no axis (its particle sits at its centre)
  double sin_th, cos_th;
  ::sincos(bth_[b], &sin_th, &cos_th);  // glibc: the same bits as sin() and cos(), in one call
  bux_[b] = -sin_th;
  buy_[b] = cos_th;
}

// Body b's particles at its pose and shape (the body's values read once:
// stores to the particles' arrays could otherwise alias them).
[[gnu::always_inline]] inline void DemSolver::place_particles_of(std::size_t b) {
  const double x = bx_[b], y = by_[b], ux = bux_[b], uy = buy_[b], s = bs_[b], sdot = bsdot_[b];
  const double vx = bvx_[b], vy = bvy_[b], w = bw_[b], r = br_[b];
  for (int j = body_particle_start_[b]; j < body_particle_start_[b + 1]; ++j) {
    const auto i = static_cast<std::size_t>(body_particle_[j]);
    const double ox = pa_[i] * s * ux, oy = pa_[i] * s * uy;
    px_[i] = x + ox;
    py_[i] = y + oy;
    // Velocity of the particle's centre: rigid motion plus its slide along the axis.
    const double slide = pa_[i] * sdot;
    pvx_[i] = vx - w * oy + slide * ux;
    pvy_[i] = vy + w * ox + slide * uy;
    pr_[i] = r;
    pw_[i] = w;
  }
}

// The first half of a velocity Verlet step for every body, and the sums
// over the new particles (or bodies) of the strain's least-squares fit and of
// the contact list's affine fit: one pass over each body and its particles,
// in kStepParts fixed parts (equal particle counts), each part summed in
// order and the parts in part order, so the sums have the same bits for any
// number of threads. (Kick, drift, shape, axis, particles and the two fits
// were eight passes over the bodies or particles, each ended by a wait for
// all threads.)
DemSolver::StepSums DemSolver::move_bodies(double dt_s) {
  const bool by_particle = spec_.strain_bodies == StrainBodies::particles;
  const double h = 0.5 * dt_s, inv_dt = 1 / dt_s;
  std::array<StepSums, kStepParts> part;
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kStepParts; ++k) {
    StepSums sum{};  // (in registers: part[k] could alias the arrays read)
    for (std::size_t b = part_first_body_[k]; b < part_first_body_[k + 1]; ++b) {
      kick_body(b, h);
      drift_and_reshape(b, dt_s);
      place_particles_of(b);
      // (Two loops over the body's particles, which are in L1 by now: the
      // two fits' 17 sums at once would not fit in registers.)
      const int first = body_particle_start_[b], last = body_particle_start_[b + 1];
      if (detector_)
        detector_->add_fit_terms(body_particle_.data() + first, last - first, px_.data(), py_.data(), origin_x_,
                                 origin_y_, sum.fit);
      if (by_particle)
        for (int j = first; j < last; ++j) {
          const auto i = static_cast<std::size_t>(body_particle_[j]);
          add_strain_terms(sum.strain, 0.5 * (px_[i] + px_old_[i]) - origin_x_, 0.5 * (py_[i] + py_old_[i]) - origin_y_,
                           (px_[i] - px_old_[i]) * inv_dt, (py_[i] - py_old_[i]) * inv_dt);
        }
      else
        add_strain_terms(sum.strain, bx_[b] - h * bvx_[b] - origin_x_, by_[b] - h * bvy_[b] - origin_y_, bvx_[b],
                         bvy_[b]);
    }
    part[k] = sum;
  }
  StepSums total{};
  for (const auto& p : part) {
    for (std::size_t j = 0; j < total.strain.size(); ++j) total.strain[j] += p.strain[j];
    for (std::size_t j = 0; j < total.fit.size(); ++j) total.fit[j] += p.fit[j];
  }
  return total;
}

// The terms of the fit alpha = (sum V~ x~^T)(sum x~ x~^T)^+ of one particle
// or body: position x, y (from the tissue's centre) and velocity vx, vy.
[[gnu::always_inline]] inline void DemSolver::add_strain_terms(StrainSums& acc, double x, double y, double vx, double vy) {
  const double terms[11] = {x, y, vx, vy, x * x, x * y, y * y, vx * x, vx * y, vy * x, vy * y};
  for (std::size_t k = 0; k < 11; ++k) acc[k] += terms[k];
}

// One block of contacts' kinematics, in and out of the law (per thread).
struct DemSolver::BlockScratch {
  alignas(64) double gap[kBlock], dn[kBlock], ds[kBlock], dth[kBlock], nx[kBlock], ny[kBlock];
  alignas(64) double lp[kBlock], lq[kBlock], fn[kBlock], fs[kBlock], mt[kBlock];
};

// Forces per contact in parallel (blocks of bonds, then of contacts), then
// their sums per body, each from its own contacts in a fixed order, and the
// closing half kick of h_s with them (bodies in the step's fixed parts, on
// the thread that moves them).
void DemSolver::compute_forces_and_kick(double dt_s, double h_s) {
  const std::size_t bond_blocks = (bonds_.size() + kBlock - 1) / kBlock;
  const std::size_t blocks = bond_blocks + (contacts_.size() + kBlock - 1) / kBlock;
#pragma omp parallel
  {
    BlockScratch scratch;
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < blocks; ++k) {
      const bool bond = k < bond_blocks;
      BondSet& set = bond ? bonds_ : contacts_;
      const std::size_t begin = (bond ? k : k - bond_blocks) * kBlock;
      const std::size_t number = bond ? begin : bonds_.size() + begin;
      contact_block(set, begin, std::min(kBlock, set.size() - begin), number, dt_s, scratch);
    }
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = part_first_body_[k]; b < part_first_body_[k + 1]; ++b) {
        sum_forces_on_body(b);
        kick_body(b, h_s);
      }
  }
}

// Contacts [begin, begin + count) of a set, numbered from `number` on: their
// kinematics, the law, and the forces and moments they put on their ends.
void DemSolver::contact_block(BondSet& set, std::size_t begin, std::size_t count, std::size_t number,
                              double dt_s, BlockScratch& s) {
  const int* const P = set.p.data() + begin;
  const int* const Q = set.q.data() + begin;
  const double *const x = px_.data(), *const y = py_.data(), *const r = pr_.data();
  const double *const vx = pvx_.data(), *const vy = pvy_.data(), *const w = pw_.data();
#pragma omp simd
  for (std::size_t j = 0; j < count; ++j) {
    const int p = P[j], q = Q[j];
    const double dx = x[q] - x[p], dy = y[q] - y[p];
    const double d = std::sqrt(dx * dx + dy * dy);
    const double d_or_1 = d > 0 ? d : 1.0;  // divide unconditionally (SIMD lanes), select after
    const double nx = d > 0 ? dx / d_or_1 : 1.0, ny = d > 0 ? dy / d_or_1 : 0.0;
    const double gap = d - r[p] - r[q];
    // Contact point relative to each centre: lp n and -lq n.
    const double lp = r[p] + 0.5 * gap, lq = r[q] + 0.5 * gap;
    // v_c = v_centre + w x (c - centre); w x (l n) = l w (-ny, nx) = l w t.
    const double dvx = (vx[q] - vx[p]) - (lq * w[q] + lp * w[p]) * (-ny);
    const double dvy = (vy[q] - vy[p]) - (lq * w[q] + lp * w[p]) * nx;
    s.gap[j] = gap;
    s.nx[j] = nx;
    s.ny[j] = ny;
    s.lp[j] = lp;
    s.lq[j] = lq;
    s.dn[j] = (dvx * nx + dvy * ny) * dt_s;
    s.ds[j] = (-dvx * ny + dvy * nx) * dt_s;
    s.dth[j] = (w[q] - w[p]) * dt_s;
    s.mt[j] = 0;
  }
  law_->update(set, BondBlock{begin, count, s.gap, s.dn, s.ds, s.dth, s.fn, s.fs, s.mt}, dt_s);
  // Force on q (minus on p); moments on each end: the law's, and the shear
  // force's about the centre: (c - x_q) x f = -lq fs, (c - x_p) x (-f) = -lp fs.
  ContactForce* const out = contact_force_.data() + number;
  for (std::size_t j = 0; j < count; ++j) {
    out[j].fx = s.fn[j] * s.nx[j] - s.fs[j] * s.ny[j];
    out[j].fy = s.fn[j] * s.ny[j] + s.fs[j] * s.nx[j];
    out[j].moment[0] = -s.mt[j] - s.lp[j] * s.fs[j];
    out[j].moment[1] = s.mt[j] - s.lq[j] * s.fs[j];
  }
}

// F = sum f, T = sum (t_p + (x_p - x_G) x f_p) over the body's particles, each
// particle's f and t summed over its contacts in their order.
void DemSolver::sum_forces_on_body(std::size_t b) {
  double fx = 0, fy = 0, tq = 0;
  for (int k = body_particle_start_[b]; k < body_particle_start_[b + 1]; ++k) {
    const int i = body_particle_[k];
    double pfx = 0, pfy = 0, ptq = 0;
    for (const int* e = particle_contacts_.begin(i); e != particle_contacts_.end(i); ++e) {
      const ContactForce& f = contact_force_[ContactIncidence::contact(*e)];
      const bool q = ContactIncidence::is_q(*e);
      const double sign = q ? 1.0 : -1.0;
      pfx += sign * f.fx;
      pfy += sign * f.fy;
      ptq += f.moment[q];
    }
    fx += pfx;
    fy += pfy;
    tq += ptq + (px_[i] - bx_[b]) * pfy - (py_[i] - by_[b]) * pfx;
  }
  bfx_[b] = fx;
  bfy_[b] = fy;
  btq_[b] = tq;
}

// The per-contact force arrays and each particle's list of contacts, after
// the contacts changed.
void DemSolver::index_contacts() {
  const std::size_t n = bonds_.size() + contacts_.size();
  contact_force_.resize(n);
  contact_kt_.resize(n);
  contact_kr_.resize(2 * n);
  particle_contacts_.build(px_.size(), bonds_, contacts_);
  body_contacts_.build(bx_.size(), bonds_, contacts_, pbody_.data());
}

void DemSolver::step(double dt_ms) {
  if (!(dt_ms > 0) || dt_ms > stable_step_ms_ * (1 + 1e-12))
    throw std::invalid_argument("mechanics step " + fmt(dt_ms) + " ms refused: the stable DEM step is " +
                                fmt(stable_step_ms_) + " ms");
  const double dt = dt_ms * 1e-3;
  // Half kick with the forces of the present state, drift, new geometry
  // (length ratios at the end of the step), particles.
  px_old_.swap(px_);
  py_old_.swap(py_);
  const StepSums sums = move_bodies(dt);
  if (detector_ && detector_->needs_rebuild(sums.fit, origin_x_, origin_y_, px_.data(), py_.data(), pr_.data()))
    rebuild_contacts();
  add_strain(sums.strain, dt);
  compute_forces_and_kick(dt, 0.5 * dt);
  time_s_ += dt;
  ++steps_;
  out_dirty_ = true;
}

// Strain rate: the least-squares velocity gradient from the sums over
// particles or bodies; eps += sym(alpha) dt.
void DemSolver::add_strain(const StrainSums& sums, double dt_s) {
  const std::size_t n = spec_.strain_bodies == StrainBodies::particles ? px_.size() : bx_.size();
  const auto [sx, sy, svx, svy, sxx, sxy, syy, vxx, vxy, vyx, vyy] = sums;
  // Never a silent NaN: a body gone non-finite stops the run here, naming the time.
  if (!std::isfinite(sx + sy + svx + svy))
    throw std::runtime_error("DEM: a body's position or velocity became non-finite at t = " +
                             fmt((time_s_ + dt_s) * 1e3) + " ms (the mechanics went unstable)");
  if (n < 2) return;
  const double inv_n = 1.0 / static_cast<double>(n);
  const double mx = sx * inv_n, my = sy * inv_n, mvx = svx * inv_n, mvy = svy * inv_n;
  Eigen::Matrix2d S, V;
  S << sxx - n * mx * mx, sxy - n * mx * my, sxy - n * mx * my, syy - n * my * my;
  V << vxx - n * mvx * mx, vxy - n * mvx * my, vyx - n * mvy * mx, vyy - n * mvy * my;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
  const Eigen::Vector2d ev = eig.eigenvalues();  // ascending
  Eigen::Matrix2d alpha = Eigen::Matrix2d::Zero();
  if (ev(0) > 1e-10 * ev(1)) {
    alpha = V * S.inverse();
  } else if (ev(1) > 0) {
    // Bodies on a line u: only the stretch rate along u is defined.
    const Eigen::Vector2d u = eig.eigenvectors().col(1);
    alpha = (u.dot(V * u) / ev(1)) * u * u.transpose();
  }
  strain_[0] += alpha(0, 0) * dt_s;
  strain_[1] += alpha(1, 1) * dt_s;
  strain_[2] += 0.5 * (alpha(0, 1) + alpha(1, 0)) * dt_s;
}

template <class Self, class F>
void DemSolver::for_each_evolving_array(Self& self, F&& f) {
  // Bodies: pose, velocity, force, and the clump's shape on its way to the target.
  f("dem.body.x", self.bx_), f("dem.body.y", self.by_), f("dem.body.theta", self.bth_);
  f("dem.body.vx", self.bvx_), f("dem.body.vy", self.bvy_), f("dem.body.omega", self.bw_);
  f("dem.body.fx", self.bfx_), f("dem.body.fy", self.bfy_), f("dem.body.torque", self.btq_);
  f("dem.body.r", self.br_), f("dem.body.s", self.bs_), f("dem.body.sdot", self.bsdot_), f("dem.body.lambda", self.blambda_);
  f("dem.body.target_r", self.btarget_r_), f("dem.body.target_s", self.btarget_s_), f("dem.body.ux", self.bux_), f("dem.body.uy", self.buy_);
  // Particles, now and a step ago (the strain's half-step velocities).
  f("dem.particle.x", self.px_), f("dem.particle.y", self.py_), f("dem.particle.x_old", self.px_old_), f("dem.particle.y_old", self.py_old_);
  f("dem.particle.vx", self.pvx_), f("dem.particle.vy", self.pvy_), f("dem.particle.r", self.pr_), f("dem.particle.omega", self.pw_);
}

namespace {

// A BondSet's every array (constants too: contacts come and go with the list).
template <class Set, class F>
void for_each_bond_array(Set& set, const std::string& prefix, F&& f) {
  f(prefix + "p", set.p), f(prefix + "q", set.q), f(prefix + "kn", set.kn), f(prefix + "ks", set.ks);
  f(prefix + "m_eff", set.m_eff), f(prefix + "ref_gap", set.ref_gap), f(prefix + "cn", set.cn), f(prefix + "cs", set.cs);
  f(prefix + "kb", set.kb), f(prefix + "fn", set.fn), f(prefix + "fs", set.fs), f(prefix + "mb", set.mb);
  f(prefix + "intact", set.intact);
}

void put_array(CheckpointFields& fields, const std::string& name, const std::vector<double>& v) { fields.put(name, v); }
void put_array(CheckpointFields& fields, const std::string& name, const std::vector<int>& v) { fields.put(name, v); }
void put_array(CheckpointFields& fields, const std::string& name, const std::vector<std::uint8_t>& v) {
  fields.put_bytes(name, v.data(), v.size());
}

// Reads a field of `count` values (count < 0: as many as it has).
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<double>& v, long long count) {
  v = fields.numbers(name, count);
}
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<int>& v, long long count) {
  v = fields.ints(name, count);
}
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<std::uint8_t>& v,
               long long count) {
  v.resize(static_cast<std::size_t>(count));
  fields.bytes(name, v.data(), v.size());
}

}  // namespace

void DemSolver::save(CheckpointFields& fields) const {
  for_each_evolving_array(*this, [&](const std::string& name, const std::vector<double>& v) { fields.put(name, v); });
  for_each_bond_array(bonds_, "dem.bond.", [&](const std::string& name, const auto& v) { put_array(fields, name, v); });
  for_each_bond_array(contacts_, "dem.contact.",
                      [&](const std::string& name, const auto& v) { put_array(fields, name, v); });
  if (detector_) detector_->save(fields);
  fields.put("dem.clock", std::vector<double>{time_s_, static_cast<double>(steps_), stable_step_ms_, strain_[0],
                                              strain_[1], strain_[2]});
}

void DemSolver::load(const CheckpointFields& fields) {
  for_each_evolving_array(*this, [&](const std::string& name, std::vector<double>& v) { fields.read_into(name, v); });
  const long long bonds = static_cast<long long>(bonds_.size());
  for_each_bond_array(bonds_, "dem.bond.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, bonds); });
  const long long contacts = static_cast<long long>(fields.integers("dem.contact.p").size());
  for_each_bond_array(contacts_, "dem.contact.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, contacts); });
  const long long particles = static_cast<long long>(px_.size());
  for (std::size_t k = 0; k < bonds_.size() + contacts_.size(); ++k) {
    const BondSet& set = k < bonds_.size() ? bonds_ : contacts_;
    const std::size_t i = k < bonds_.size() ? k : k - bonds_.size();
    if (set.p[i] < 0 || set.p[i] >= particles || set.q[i] < 0 || set.q[i] >= particles)
      throw CheckpointError("its DEM contact " + std::to_string(k) + " joins particles outside the tissue");
  }
  if (detector_) detector_->load(fields);
  const auto clock = fields.numbers("dem.clock", 6);
  // (A stable step far below the bonded tissue's own would stall the run:
  // contacts never lower it that much.)
  if (!(clock[2] >= 0.1 * bonded_stable_step_ms_ && clock[2] <= 1e3) || !(clock[1] >= 0 && clock[1] < 1e18))
    throw CheckpointError("its DEM clock (steps, stable step) is out of range");
  time_s_ = clock[0];
  steps_ = static_cast<std::size_t>(clock[1]);
  stable_step_ms_ = clock[2];
  strain_ = {clock[3], clock[4], clock[5]};
  index_contacts();
  out_dirty_ = true;
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

std::size_t DemSolver::broken_bonds() const {
  return static_cast<std::size_t>(std::count(bonds_.intact.begin(), bonds_.intact.end(), 0));
}

std::string DemSolver::report() const {
  std::string r = std::to_string(steps_) + " steps, stable step now " + fmt(stable_step_ms_) + " ms; " +
                  std::to_string(bonds_.size()) + " bonds (" + std::to_string(broken_bonds()) + " broken)";
  if (detector_)
    r += "; unbonded contacts: " + std::to_string(touching_contacts()) + " touching of " +
         std::to_string(contacts_.size()) + " listed, list built " + std::to_string(detector_->builds()) + " times";
  else
    r += "; no contact detection";
  return r;
}

std::size_t DemSolver::touching_contacts() const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < contacts_.size(); ++k) n += contacts_.fn[k] > 0;
  return n;
}

double DemSolver::kinetic_energy_J() const {
  double e = 0;
  for (std::size_t b = 0; b < bx_.size(); ++b)
    e += 0.5 * mass_[b] * (bvx_[b] * bvx_[b] + bvy_[b] * bvy_[b]) + 0.5 * inertia_[b] * bw_[b] * bw_[b];
  return e;
}

double DemSolver::elastic_energy_J() const {
  double e = 0;
  for (const BondSet* set : {&bonds_, &contacts_})
    for (std::size_t k = 0; k < set->size(); ++k) {
      e += 0.5 * set->fn[k] * set->fn[k] / set->kn[k];
      if (set->ks[k] > 0) e += 0.5 * set->fs[k] * set->fs[k] / set->ks[k];
      if (set->kb[k] > 0) e += 0.5 * set->mb[k] * set->mb[k] / set->kb[k];
    }
  return e;
}

std::unique_ptr<MechanicsSolver> make_mechanics_solver(const Tissue& tissue, const DemSpec& spec) {
  if (spec.solver != "dem") throw std::invalid_argument("unknown mechanics solver '" + spec.solver + "'");
  return std::make_unique<DemSolver>(tissue, spec);
}

}  // namespace fibrodem
