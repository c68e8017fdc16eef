// The tissue's strain (dem_strain.hpp): the least-squares velocity gradient
// of the particles (or bodies) each step, its symmetric part summed.
#include "mechanics/dem_strain.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "util/number_text.hpp"

namespace fibrodem {

void DemStrainFit::add(const Sums& sums, std::size_t n, double dt_s, double t_end_ms) {
  const auto [sx, sy, svx, svy, sxx, sxy, syy, vxx, vxy, vyx, vyy] = sums;
  // Never a silent NaN: a body gone non-finite stops the run here, naming the time.
  if (!std::isfinite(sx + sy + svx + svy))
    throw std::runtime_error("DEM: a body's position or velocity became non-finite at t = " +
                             significant_digits(t_end_ms, 6) + " ms (the mechanics went unstable)");
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

}  // namespace fibrodem
