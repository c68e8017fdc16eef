// The tissue's strain (dem_solver.hpp, "Strain"): each step, the
// least-squares velocity gradient alpha = (sum V~ x~^T)(sum x~ x~^T)^+ of
// the particles (or bodies), from sums the step's move loop takes; eps +=
// sym(alpha) dt.
#pragma once

#include <array>
#include <cstddef>

namespace fibrodem {

class DemStrainFit {
 public:
  // The fit's sums: x, y, vx, vy, xx, xy, yy, vx x, vx y, vy x, vy y.
  using Sums = std::array<double, 11>;

  // The terms of one particle or body: position x, y (from the tissue's
  // centre) and velocity vx, vy. Forced inline: the step's move loop calls
  // it once per particle.
  [[gnu::always_inline]] static void add_terms(Sums& acc, double x, double y, double vx, double vy) {
    const double terms[11] = {x, y, vx, vy, x * x, x * y, y * y, vx * x, vx * y, vy * x, vy * y};
    for (std::size_t k = 0; k < 11; ++k) acc[k] += terms[k];
  }
  // eps += sym(alpha) dt_s from the sums over n particles or bodies; throws
  // std::runtime_error, naming t_end_ms, if a sum is not finite.
  void add(const Sums& sums, std::size_t n, double dt_s, double t_end_ms);

  const std::array<double, 3>& strain() const { return strain_; }
  void set_strain(const std::array<double, 3>& eps) { strain_ = eps; }

 private:
  std::array<double, 3> strain_{0, 0, 0};  // eps_xx, eps_yy, eps_xy
};

}  // namespace fibrodem
