#include "mechanics/contact_detector.hpp"

#include "mechanics/ordered_sum.hpp"
#include "model/work_split.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fibrodem {

ContactDetector::ContactDetector(std::vector<int> body, const std::vector<std::pair<int, int>>& bonded,
                                 double skin_m)
    : body_(std::move(body)), skin_(skin_m) {
  if (!(skin_ > 0)) throw std::invalid_argument("contact detection: the skin must be > 0");
  const std::size_t n = body_.size();
  partner_begin_.assign(n + 1, 0);
  for (const auto& [p, q] : bonded) {
    ++partner_begin_[p + 1];
    ++partner_begin_[q + 1];
  }
  for (std::size_t i = 0; i < n; ++i) partner_begin_[i + 1] += partner_begin_[i];
  partner_.resize(partner_begin_[n]);
  std::vector<int> fill(partner_begin_.begin(), partner_begin_.end() - 1);
  for (const auto& [p, q] : bonded) {
    partner_[fill[p]++] = q;
    partner_[fill[q]++] = p;
  }
  for (std::size_t i = 0; i < n; ++i)
    std::sort(partner_.begin() + partner_begin_[i], partner_.begin() + partner_begin_[i + 1]);
}

bool ContactDetector::bonded(int p, int q) const {
  const auto first = partner_.begin() + partner_begin_[p], last = partner_.begin() + partner_begin_[p + 1];
  return std::binary_search(first, last, q);
}

bool ContactDetector::needs_rebuild(const double* x, const double* y, const double* r) const {
  const auto sums = ordered_sum<6>(body_.size(), [&](std::size_t i, FitSums& acc) {
    const int id = static_cast<int>(i);
    add_fit_terms(&id, 1, x, y, 0.0, 0.0, acc);
  });
  return needs_rebuild(sums, 0.0, 0.0, x, y, r);
}

bool ContactDetector::needs_rebuild(const FitSums& sums, double origin_x, double origin_y, const double* x,
                                    const double* y, const double* r) const {
  if (builds_ == 0) return true;
  const AffineFit fit = affine_fit(sums, origin_x, origin_y);
  return beyond_skin(fit, departure(fit, x, y, r, 0, body_.size()));
}

// Best-fit affine map from the built positions to these: A = M S0^-1,
// M = sum (x - c)(x0 - c0)^T = sum (x - o)(x0 - c0)^T - (c - o) e0^T,
// e0 = sum (x0 - c0), o the sums' origin.
ContactDetector::AffineFit ContactDetector::affine_fit(const FitSums& sums, double origin_x, double origin_y) const {
  const double inv_n = 1.0 / static_cast<double>(body_.size());
  const double cx_o = sums[0] * inv_n, cy_o = sums[1] * inv_n;  // c - o
  AffineFit fit;
  fit.cx = origin_x + cx_o;
  fit.cy = origin_y + cy_o;
  if (affine_) {
    const double mxx = sums[2] - cx_o * ex0_, mxy = sums[3] - cx_o * ey0_;
    const double myx = sums[4] - cy_o * ex0_, myy = sums[5] - cy_o * ey0_;
    fit.a00 = mxx * s0inv_[0][0] + mxy * s0inv_[1][0];
    fit.a01 = mxx * s0inv_[0][1] + mxy * s0inv_[1][1];
    fit.a10 = myx * s0inv_[0][0] + myy * s0inv_[1][0];
    fit.a11 = myx * s0inv_[0][1] + myy * s0inv_[1][1];
  }
  return fit;
}

// The largest departure from the affine motion and the largest radius
// growth; a non-finite position or radius is flagged (the build then names
// it): v * 0 is NaN only for a NaN or infinite v, and sums keep a NaN, while
// plain maxima keep the loop in SIMD lanes. Maxima: any order gives them.
// Threads take runs of kMaxBlock particles, each reduced in SIMD lanes
// apart: clang 14 at -O1 keeps one lane of a combined `parallel for simd`
// reduction (a sum comes out a quarter of itself on AVX2, a maximum misses
// particles), so this list was kept past moves that needed a new one, and
// which particles it missed depended on the thread count.
ContactDetector::Departure ContactDetector::departure(const AffineFit& fit, const double* x, const double* y,
                                                      const double* r, std::size_t begin, std::size_t end) const {
  constexpr std::size_t kMaxBlock = 512;
  const std::size_t blocks = (end - begin + kMaxBlock - 1) / kMaxBlock;
  const double cx = fit.cx, cy = fit.cy, a00 = fit.a00, a01 = fit.a01, a10 = fit.a10, a11 = fit.a11;
  double u2 = 0, dr = 0, probe = 0;
#pragma omp parallel for schedule(static) reduction(max : u2, dr) reduction(+ : probe)
  for (std::size_t k = 0; k < blocks; ++k) {
    double block_u2 = 0, block_dr = 0, block_probe = 0;
    const std::size_t first = begin + k * kMaxBlock, last = std::min(end, first + kMaxBlock);
#pragma omp simd reduction(max : block_u2, block_dr) reduction(+ : block_probe)
    for (std::size_t i = first; i < last; ++i) {
      const double dx0 = x0_[i] - cx0_, dy0 = y0_[i] - cy0_;
      const double ux = x[i] - cx - (a00 * dx0 + a01 * dy0), uy = y[i] - cy - (a10 * dx0 + a11 * dy0);
      const double u2_i = ux * ux + uy * uy, dr_i = r[i] - r0_[i];
      block_u2 = u2_i > block_u2 ? u2_i : block_u2;
      block_dr = dr_i > block_dr ? dr_i : block_dr;
      block_probe += (u2_i + dr_i) * 0.0;
    }
    u2 = std::max(u2, block_u2);
    dr = std::max(dr, block_dr);
    probe += block_probe;
  }
  return {u2, dr, std::isnan(probe) ? 1.0 : 0.0};
}

bool ContactDetector::beyond_skin(const AffineFit& fit, const Departure& d) const {
  if (builds_ == 0 || d.not_finite != 0) return true;
  // Smallest singular value of A (2 x 2): s^2 = (T - sqrt(T^2 - 4 D^2)) / 2.
  const double t = fit.a00 * fit.a00 + fit.a01 * fit.a01 + fit.a10 * fit.a10 + fit.a11 * fit.a11;
  const double det = fit.a00 * fit.a11 - fit.a01 * fit.a10;
  const double s_min = std::sqrt(std::max(0.0, 0.5 * (t - std::sqrt(std::max(0.0, t * t - 4 * det * det)))));
  const double worst_r = s_min < 1 ? 2 * rmax0_ : 0.0;
  return !(s_min * (worst_r + skin_) - worst_r >= 2 * (std::sqrt(d.u2) + std::max(0.0, d.dr)));
}

// e0 = sum (x0 - c0) of the built positions: zero but for rounding, which
// the affine fit from sums taken from another origin takes out.
void ContactDetector::remember_offset_sums() {
  ex0_ = ey0_ = 0;
  for (std::size_t i = 0; i < x0_.size(); ++i) {
    ex0_ += x0_[i] - cx0_;
    ey0_ += y0_[i] - cy0_;
  }
}

// The centroid and inverse second moment of the built positions, for the
// affine fit in needs_rebuild().
void ContactDetector::remember_moments() {
  const std::size_t n = x0_.size();
  cx0_ = cy0_ = rmax0_ = 0;
  for (std::size_t i = 0; i < n; ++i) {
    cx0_ += x0_[i] / static_cast<double>(n);
    cy0_ += y0_[i] / static_cast<double>(n);
    rmax0_ = std::max(rmax0_, r0_[i]);
  }
  remember_offset_sums();
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = x0_[i] - cx0_, dy = y0_[i] - cy0_;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  const double det = sxx * syy - sxy * sxy;
  affine_ = n >= 3 && det > 1e-10 * (sxx + syy) * (sxx + syy);
  if (!affine_) return;
  s0inv_[0][0] = syy / det;
  s0inv_[0][1] = s0inv_[1][0] = -sxy / det;
  s0inv_[1][1] = sxx / det;
}

void ContactDetector::build(const double* x, const double* y, const double* r,
                            std::vector<std::pair<int, int>>& pairs) {
  const std::size_t n = body_.size();
  pairs.clear();
  x0_.resize(n);
  y0_.resize(n);
  r0_.resize(n);
  // One parallel pass: the positions kept, the first non-finite particle, the
  // bounding box and the largest radius (minima and maxima: any order gives
  // them). (Serial, the build's passes over the particles took a fifth of
  // its time on two threads in the Fig. 3 EM scene.)
  std::size_t bad = n;
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL, rmax = 0;
#pragma omp parallel for schedule(static) reduction(min : bad, xmin, ymin) reduction(max : xmax, ymax, rmax)
  for (std::size_t i = 0; i < n; ++i) {
    x0_[i] = x[i];
    y0_[i] = y[i];
    r0_[i] = r[i];
    if (!std::isfinite(x[i] + y[i] + r[i])) bad = std::min(bad, i);
    xmin = std::min(xmin, x[i]);
    xmax = std::max(xmax, x[i]);
    ymin = std::min(ymin, y[i]);
    ymax = std::max(ymax, y[i]);
    rmax = std::max(rmax, r[i]);
  }
  if (bad < n)
    throw std::runtime_error("contact detection: particle " + std::to_string(bad) +
                             " has a non-finite position or radius (the mechanics went unstable)");
  ++builds_;
  remember_moments();
  if (n < 2) return;
  // Cells no smaller than the largest cut-off, and not many more than particles.
  double h = 2 * rmax + skin_;
  const double area = (xmax - xmin + h) * (ymax - ymin + h);
  h = std::max(h, std::sqrt(area / (4.0 * static_cast<double>(n))));
  const long nx = static_cast<long>((xmax - xmin) / h) + 1, ny = static_cast<long>((ymax - ymin) / h) + 1;
  const std::size_t ncell = static_cast<std::size_t>(nx * ny);
  // Counting sort of the particles by cell (stable: ascending index within a cell).
  cell_of_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const long cx = std::min(nx - 1, static_cast<long>((x[i] - xmin) / h));
    const long cy = std::min(ny - 1, static_cast<long>((y[i] - ymin) / h));
    cell_of_[i] = static_cast<int>(cy * nx + cx);
  }
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_of_[i] + 1];
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  order_.resize(n);
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[cell_fill_[cell_of_[i]]++] = static_cast<int>(i);
  // Each particle's pairs, in kChunks fixed runs of particles taken by the
  // threads as they come free (particles at the tissue's edges and in loose
  // regions have fewer neighbours), joined in run order: the serial list.
  chunk_pairs_.resize(kChunks);
  for_each_block(static_cast<long>(kChunks), [&](long chunk) {
    const auto k = static_cast<std::size_t>(chunk);
    std::vector<std::pair<int, int>>& mine = chunk_pairs_[k];
    mine.clear();
    for (std::size_t i = n * k / kChunks; i < n * (k + 1) / kChunks; ++i)
      add_pairs_of(static_cast<int>(i), x, y, r, nx, ny, mine);
  });
  for (const auto& part : chunk_pairs_) pairs.insert(pairs.end(), part.begin(), part.end());
}

// The candidates q > p of particle p in its 3 x 3 block of cells, ascending.
void ContactDetector::add_pairs_of(int p, const double* x, const double* y, const double* r, long nx, long ny,
                                   std::vector<std::pair<int, int>>& pairs) const {
  const long cx = cell_of_[p] % nx, cy = cell_of_[p] / nx;
  const std::size_t first = pairs.size();
  for (long gy = std::max(0L, cy - 1); gy <= std::min(ny - 1, cy + 1); ++gy)
    for (long gx = std::max(0L, cx - 1); gx <= std::min(nx - 1, cx + 1); ++gx) {
      const long c = gy * nx + gx;
      for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const int q = order_[k];
        if (q <= p || body_[q] == body_[p]) continue;
        const double dx = x[q] - x[p], dy = y[q] - y[p], cut = r[p] + r[q] + skin_;
        if (dx * dx + dy * dy >= cut * cut || bonded(p, q)) continue;
        pairs.emplace_back(p, q);
      }
    }
  std::sort(pairs.begin() + static_cast<long>(first), pairs.end());
}

void ContactDetector::save(CheckpointFields& fields) const {
  fields.put_integer("dem.detector.builds", static_cast<long long>(builds_));
  fields.put("dem.detector.x0", x0_);
  fields.put("dem.detector.y0", y0_);
  fields.put("dem.detector.r0", r0_);
  fields.put("dem.detector.frame", std::vector<double>{cx0_, cy0_, rmax0_, s0inv_[0][0], s0inv_[0][1], s0inv_[1][0],
                                                       s0inv_[1][1], affine_ ? 1.0 : 0.0});
}

void ContactDetector::load(const CheckpointFields& fields) {
  builds_ = static_cast<std::size_t>(fields.integer("dem.detector.builds"));
  x0_ = fields.numbers("dem.detector.x0");
  if (!x0_.empty() && x0_.size() != body_.size())
    throw CheckpointError("its contact list was built for " + std::to_string(x0_.size()) + " particles, the tissue has " +
                          std::to_string(body_.size()));
  y0_ = fields.numbers("dem.detector.y0", static_cast<long long>(x0_.size()));
  r0_ = fields.numbers("dem.detector.r0", static_cast<long long>(x0_.size()));
  const auto f = fields.numbers("dem.detector.frame", 8);
  cx0_ = f[0], cy0_ = f[1], rmax0_ = f[2];
  s0inv_[0][0] = f[3], s0inv_[0][1] = f[4], s0inv_[1][0] = f[5], s0inv_[1][1] = f[6];
  affine_ = f[7] != 0;
  remember_offset_sums();
}

}  // namespace fibrodem
