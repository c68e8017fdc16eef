#include "mechanics/clump_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace fibrodem {
namespace {

// Solves f(r) = 0 for r in (lo, hi) with f(lo) < 0 < f(hi), f increasing:
// Newton steps kept inside a shrinking bracket (bisection when they leave it).
// f_df(r) returns {f(r), f'(r)} (one evaluation of the shared asin and sqrt).
// A Newton step of delta leaves an error of about delta^2 f''/(2 f'), here
// ~delta^2 / (2 r) (the areas grow like r^2): after a step below 1e-9 r the
// root is known to rounding, so it is taken without a further evaluation
// (from the last step's radius a solve then costs two evaluations, not three).
template <class FDF>
double bracketed_newton(FDF f_df, double lo, double hi, double guess) {
  constexpr double kConverged = 1e-9;  // Newton step / r after which the error is ~1e-18 r
  double r = std::clamp(guess, lo, hi);
  for (int it = 0; it < 200; ++it) {
    const auto [v, d] = f_df(r);
    if (v == 0) return r;
    if (v < 0) lo = r;
    else hi = r;
    const double newton = d > 0 ? r - v / d : lo;
    const bool inside = newton > lo && newton < hi;
    const double next = inside ? newton : 0.5 * (lo + hi);
    if (inside && std::abs(next - r) <= kConverged * std::abs(r)) return next;
    if (std::abs(next - r) <= 1e-15 * std::abs(r) || hi - lo <= 1e-15 * hi) return next;
    r = next;
  }
  return r;
}

// The union's area and its slopes in r and s (one asin, one sqrt).
struct UnionArea {
  double area, d_dr, d_ds;
};
UnionArea union_area_and_slopes(int n, double r, double s) {
  const double h = std::min(0.5 * s, r);
  const double root = std::sqrt(std::max(0.0, r * r - h * h));
  const double angle = std::asin(std::min(1.0, h / r));
  const double strip = 0.5 * (h * root + r * r * angle);  // half the union's area over a strip of half-width h
  return {M_PI * r * r + 4.0 * (n - 1) * strip, 2 * M_PI * r + 4.0 * (n - 1) * r * angle, 2.0 * (n - 1) * root};
}

}  // namespace

double union_area(int n, double r, double s) { return union_area_and_slopes(n, r, s).area; }
double union_area_dr(int n, double r, double s) { return union_area_and_slopes(n, r, s).d_dr; }
double union_area_ds(int n, double r, double s) { return union_area_and_slopes(n, r, s).d_ds; }

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

ClumpShape contracted_shape(AreaRule rule, LengthMode mode, const ClumpRest& rest, double lambda,
                            double r_guess) {
  if (!(lambda > 0) || !std::isfinite(lambda))
    throw std::invalid_argument("cell length ratio must be positive, got " + std::to_string(lambda));
  // (Plain variables, not a structured binding: the lambdas below capture them.)
  const int n = rest.n;
  const double r0 = rest.r0, s0 = rest.s0, a0 = rest.area;
  if (n <= 1 || lambda == 1.0) return {r0, s0};
  const int m = n - 1;
  if (mode == LengthMode::spacing) {
    const double s = s0 * lambda;
    switch (rule) {
      case AreaRule::rectangle: return {r0 * s0 / s, s};
      case AreaRule::capsule: {
        const double b = m * s;  // pi r^2 + 2 b r - a0 = 0
        return {(-b + std::sqrt(b * b + M_PI * a0)) / M_PI, s};
      }
      case AreaRule::union_area: {
        // A(r) increases from 0 (r = 0) without bound; bracket [0, hi].
        double hi = std::max(r0, std::sqrt(a0 / M_PI));  // A(hi) >= pi hi^2 >= a0
        auto f_df = [&](double r) {
          const UnionArea u = union_area_and_slopes(n, r, s);
          return std::pair{u.area - a0, u.d_dr};
        };
        return {bracketed_newton(f_df, 0.0, hi, r_guess > 0 ? r_guess : r0 / std::sqrt(lambda)), s};
      }
    }
  }
  // Total length L = m s + 2 r fixed by lambda.
  const double length = lambda * (m * s0 + 2 * r0);
  auto spacing = [&](double r) { return (length - 2 * r) / m; };
  auto fail = [&]() -> ClumpShape {
    throw std::invalid_argument("no clump shape keeps the area at length ratio " + std::to_string(lambda) +
                                " (area rule " + area_rule_name(rule) + ", length_mode total)");
  };
  switch (rule) {
    case AreaRule::rectangle: {  // 2 r (L - 2r) = a0, the smaller root
      const double disc = length * length - 4 * a0;
      if (disc < 0) return fail();
      const double r = (length - std::sqrt(disc)) / 4;
      return {r, spacing(r)};
    }
    case AreaRule::capsule: {  // 2 r (L - 2r) + pi r^2 = a0, the smaller root
      const double a = 4 - M_PI;
      const double disc = length * length - a * a0;
      if (disc < 0) return fail();
      const double r = (length - std::sqrt(disc)) / a;
      return {r, spacing(r)};
    }
    case AreaRule::union_area: {
      // g(r) = A(r, s(r)) - a0 on (0, L/2): g(0) < 0; g(L/2) = pi L^2/4 - a0.
      const double hi = 0.5 * length;
      if (M_PI * hi * hi <= a0) return fail();
      auto g_dg = [&](double r) {
        const UnionArea u = union_area_and_slopes(n, r, spacing(r));
        return std::pair{u.area - a0, u.d_dr - 2.0 / m * u.d_ds};
      };
      const double r = bracketed_newton(g_dg, 0.0, hi, r_guess > 0 ? r_guess : r0);
      return {r, spacing(r)};
    }
  }
  return {r0, s0};
}

}  // namespace fibrodem
