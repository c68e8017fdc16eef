#include "mechanics/clump_geometry.hpp"

#include "model/simd.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace fibrodem {
namespace {

using simd::fmax;
using simd::fmin;
using simd::select;

// The Newton iteration and the union's area below are written once over the
// number type: R = double for one clump, R = simd::Real for a clump per SIMD
// lane (union_shapes). Masks are bool for double.

// Solves f(r) = 0 for r in (lo, hi) with f(lo) < 0 < f(hi), f increasing:
// Newton steps kept inside a shrinking bracket (bisection when they leave it).
// f_df(r) returns {f(r), f'(r)} (one evaluation of the shared asin and sqrt).
// A Newton step of at most 1e-10 r leaves an error of order (f''/2f') step^2,
// about 1e-20 r for these smooth areas: below rounding, so it is taken
// without another evaluation to confirm it. (The DEM solves every contracting
// myocyte's shape at every step: from the radius at the step before, two
// evaluations instead of three.) In lanes, each lane keeps its root once it
// has converged while the others go on.
template <class R, class FDF>
R bracketed_newton(FDF f_df, R lo, R hi, const R& guess) {
  using Mask = decltype(R() < R());
  R r = fmin(fmax(guess, lo), hi);
  R root = r;
  Mask done(false);
  for (int it = 0; it < 200; ++it) {
    const auto [v, d] = f_df(r);
    const Mask zero = v == 0.0;
    root = select(zero && !done, r, root);
    done = done || zero;
    if (simd::all(done)) return root;
    const Mask below = v < 0.0;
    lo = select(below, r, lo);
    hi = select(below, hi, r);
    R next = select(d > 0.0, r - v / d, 0.5 * (lo + hi));
    const Mask newton = next > lo && next < hi;
    next = select(newton, next, 0.5 * (lo + hi));
    const R step = simd::fabs(next - r);
    const Mask converged =
        (newton && step <= 1e-10 * simd::fabs(r)) || step <= 1e-15 * simd::fabs(r) || hi - lo <= 1e-15 * hi;
    root = select(converged && !done, next, root);
    done = done || converged;
    if (simd::all(done)) return root;
    r = next;
  }
  return select(done, root, r);
}

// The union's area and its slopes in r and s (one asin, one sqrt); m = N - 1.
template <class R>
struct UnionArea {
  R area, d_dr, d_ds;
};
template <class R>
UnionArea<R> union_area_and_slopes(const R& m, const R& r, const R& s) {
  const R h = fmin(0.5 * s, r);
  const R root = simd::sqrt(fmax(0.0, r * r - h * h));
  const R angle = simd::asin(fmin(1.0, h / r));
  const R strip = 0.5 * (h * root + r * r * angle);  // half the union's area over a strip of half-width h
  return {M_PI * r * r + 4.0 * m * strip, 2 * M_PI * r + 4.0 * m * r * angle, 2.0 * m * root};
}

// The union rule's shape at length ratio lambda from the rest shape (m = N - 1,
// r0, s0, its area a0); `exists` false where none keeps the area (total mode).
template <class R>
struct LaneShape {
  R r, s;
};
template <class R>
LaneShape<R> union_shape(LengthMode mode, const R& m, const R& r0, const R& s0, const R& a0, const R& lambda,
                         const R& r_guess, decltype(R() < R())& exists) {
  if (mode == LengthMode::spacing) {
    // A(r) increases from 0 (r = 0) without bound; bracket [0, hi].
    const R s = s0 * lambda;
    const R hi = fmax(r0, simd::sqrt(a0 / M_PI));  // A(hi) >= pi hi^2 >= a0
    auto f_df = [&](const R& r) {
      const UnionArea<R> u = union_area_and_slopes(m, r, s);
      return std::pair{u.area - a0, u.d_dr};
    };
    exists = s == s;  // (true in every lane)
    return {bracketed_newton(f_df, R(0.0), hi, select(r_guess > 0.0, r_guess, r0 / simd::sqrt(lambda))), s};
  }
  // Total length L = m s + 2 r fixed by lambda; g(r) = A(r, s(r)) - a0 on
  // (0, L/2): g(0) < 0; g(L/2) = pi L^2/4 - a0.
  const R length = lambda * (m * s0 + 2 * r0);
  const R hi = 0.5 * length;
  exists = M_PI * hi * hi > a0;
  auto g_dg = [&](const R& r) {
    const UnionArea<R> u = union_area_and_slopes(m, r, (length - 2 * r) / m);
    return std::pair{u.area - a0, u.d_dr - 2.0 / m * u.d_ds};
  };
  const R r = bracketed_newton(g_dg, R(0.0), hi, select(r_guess > 0.0, r_guess, r0));
  return {r, (length - 2 * r) / m};
}

}  // namespace

double union_area(int n, double r, double s) { return union_area_and_slopes(n - 1.0, r, s).area; }
double union_area_dr(int n, double r, double s) { return union_area_and_slopes(n - 1.0, r, s).d_dr; }
double union_area_ds(int n, double r, double s) { return union_area_and_slopes(n - 1.0, r, s).d_ds; }

double union_polar_moment(int n, double r, double s) {
  // Disk k owns [a_k - hl, a_k + hr] of the axis; there the union's half-height
  // is y = sqrt(r^2 - u^2), u = x - a_k. With u = r sin(phi): integral of
  // (x^2 2y + 2/3 y^3) dx, by Simpson's rule in phi (a smooth integrand).
  const double h = std::min(0.5 * s, r);
  constexpr int kIntervals = 256;
  double total = 0;
  for (int k = 0; k < n; ++k) {
    const double a = (k - 0.5 * (n - 1)) * s;
    const double hl = k == 0 ? r : h, hr = k == n - 1 ? r : h;
    const double p0 = std::asin(std::clamp(-hl / r, -1.0, 1.0));
    const double p1 = std::asin(std::clamp(hr / r, -1.0, 1.0));
    const double dp = (p1 - p0) / kIntervals;
    auto g = [&](double phi) {
      const double x = a + r * std::sin(phi), y = r * std::cos(phi);
      return (x * x * 2 * y + 2.0 / 3.0 * y * y * y) * y;  // dx = r cos(phi) dphi = y dphi
    };
    double sum = g(p0) + g(p1);
    for (int i = 1; i < kIntervals; ++i) sum += (i % 2 ? 4 : 2) * g(p0 + i * dp);
    total += sum * dp / 3;
  }
  return total;
}

double rule_area(AreaRule rule, int n, double r, double s) {
  switch (rule) {
    case AreaRule::union_area: return union_area(n, r, s);
    case AreaRule::capsule: return 2 * r * (n - 1) * s + M_PI * r * r;
    case AreaRule::rectangle: return n > 1 ? 2 * r * (n - 1) * s : M_PI * r * r;
  }
  return 0;
}

ClumpRest clump_rest(AreaRule rule, int n, double r0, double s0) { return {n, r0, s0, rule_area(rule, n, r0, s0)}; }

namespace {
std::invalid_argument no_shape(AreaRule rule, double lambda) {
  return std::invalid_argument("no clump shape keeps the area at length ratio " + std::to_string(lambda) +
                               " (area rule " + area_rule_name(rule) + ", length_mode total)");
}
}  // namespace

ClumpShape contracted_shape(AreaRule rule, LengthMode mode, const ClumpRest& rest, double lambda,
                            double r_guess) {
  if (!(lambda > 0) || !std::isfinite(lambda))
    throw std::invalid_argument("cell length ratio must be positive, got " + std::to_string(lambda));
  const auto [n, r0, s0, a0] = rest;
  if (n <= 1 || lambda == 1.0) return {r0, s0};
  const int m = n - 1;
  if (rule == AreaRule::union_area) {
    bool exists = true;
    const auto [r, s] = union_shape<double>(mode, m, r0, s0, a0, lambda, r_guess, exists);
    if (!exists) throw no_shape(rule, lambda);
    return {r, s};
  }
  if (mode == LengthMode::spacing) {
    const double s = s0 * lambda;
    if (rule == AreaRule::rectangle) return {r0 * s0 / s, s};
    const double b = m * s;  // capsule: pi r^2 + 2 b r - a0 = 0
    return {(-b + std::sqrt(b * b + M_PI * a0)) / M_PI, s};
  }
  // Total length L = m s + 2 r fixed by lambda; the smaller root of
  // 2 r (L - 2r) = a0 (rectangle) or 2 r (L - 2r) + pi r^2 = a0 (capsule).
  const double length = lambda * (m * s0 + 2 * r0);
  const double a = rule == AreaRule::rectangle ? 4 : 4 - M_PI;
  const double disc = length * length - a * a0;
  if (disc < 0) throw no_shape(rule, lambda);
  const double r = (length - std::sqrt(disc)) / a;
  return {r, (length - 2 * r) / m};
}

void union_shapes(LengthMode mode, const ClumpRest* const rest[], const double lambda[], const double r_guess[],
                  std::size_t count, ClumpShape shape[], bool exists[]) {
  using simd::Real;
  constexpr std::size_t L = simd::kLanes;
  if (count == 0 || count > L) throw std::invalid_argument("union_shapes: 1 to " + std::to_string(L) + " clumps");
  alignas(64) double m[L], r0[L], s0[L], a0[L], l[L], guess[L];
  for (std::size_t i = 0; i < L; ++i) {
    const std::size_t k = std::min(i, count - 1);  // spare lanes repeat the last clump
    m[i] = rest[k]->n - 1.0, r0[i] = rest[k]->r0, s0[i] = rest[k]->s0, a0[i] = rest[k]->area;
    l[i] = lambda[k], guess[i] = r_guess[k];
  }
  Real::batch_bool_type found;
  const auto [r, s] = union_shape<Real>(mode, Real::load_aligned(m), Real::load_aligned(r0), Real::load_aligned(s0),
                                        Real::load_aligned(a0), Real::load_aligned(l), Real::load_aligned(guess), found);
  alignas(64) double r_out[L], s_out[L], found_out[L];
  r.store_aligned(r_out);
  s.store_aligned(s_out);
  select(found, Real(1.0), Real(0.0)).store_aligned(found_out);
  for (std::size_t i = 0; i < count; ++i) {
    exists[i] = found_out[i] != 0;
    if (exists[i]) shape[i] = {r_out[i], s_out[i]};
  }
}

}  // namespace fibrodem
