#include "measure/cell_strain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "model/work_split.hpp"

namespace fibrodem {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// CSR lists of `count` rows from (row, value) pairs given in ascending value
// order within each row.
template <class ForEachPair>
void build_csr(std::size_t count, std::vector<int>& start, std::vector<int>& value, ForEachPair&& for_each_pair) {
  start.assign(count + 1, 0);
  for_each_pair([&](int row, int) { ++start[static_cast<std::size_t>(row) + 1]; });
  for (std::size_t i = 0; i < count; ++i) start[i + 1] += start[i];
  value.assign(static_cast<std::size_t>(start[count]), 0);
  std::vector<int> next(start.begin(), start.end() - 1);
  for_each_pair([&](int row, int v) { value[static_cast<std::size_t>(next[row]++)] = v; });
}
}  // namespace

CellStrain::CellStrain(const Tissue& tissue) {
  const std::size_t n = tissue.cell_count();
  build_csr(n, particle_start_, particle_, [&](auto add) {
    for (std::size_t p = 0; p < tissue.particles.size(); ++p) add(tissue.particles[p].cell, static_cast<int>(p));
  });
  // Each edge (i < j) listed under both cells; sorted edges put each row in ascending order.
  std::vector<std::pair<int, int>> directed;
  directed.reserve(2 * tissue.cell_edges.size());
  for (const auto& [i, j] : tissue.cell_edges) {
    directed.emplace_back(i, j);
    directed.emplace_back(j, i);
  }
  std::sort(directed.begin(), directed.end());
  build_csr(n, neighbour_start_, neighbour_, [&](auto add) {
    for (const auto& [i, j] : directed) add(i, j);
  });

  x0_ = tissue.x_um;
  y0_ = tissue.y_um;
  centroids(tissue.particles, x0_, y0_);
  Y_inv_xx_.assign(n, kNaN);
  Y_inv_xy_.assign(n, kNaN);
  Y_inv_yy_.assign(n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    double a = 0, b = 0, d = 0;  // sum d0 d0^T = [a b; b d]
    for (int k = neighbour_start_[i]; k < neighbour_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(neighbour_[k]);
      const double dx = x0_[j] - x0_[i], dy = y0_[j] - y0_[i];
      a += dx * dx;
      b += dx * dy;
      d += dy * dy;
    }
    // Eigenvalues of the symmetric 2 x 2: mean +- radius.
    const double mean = 0.5 * (a + d), radius = std::hypot(0.5 * (a - d), b);
    if (!(mean - radius > kCollinear * (mean + radius))) {
      ++unresolved_;
      continue;
    }
    const double det = a * d - b * b;
    Y_inv_xx_[i] = d / det;
    Y_inv_xy_[i] = -b / det;
    Y_inv_yy_[i] = a / det;
  }
  x_.resize(n);
  y_.resize(n);
  for (auto* f : {&field_.E_xx, &field_.E_yy, &field_.E_xy, &field_.fibre_stretch, &field_.max_shear})
    f->assign(n, kNaN);
}

// Each cell's particles' mean, in particle order; cells without particles keep x, y as given.
void CellStrain::centroids(const std::vector<Particle>& particles, std::vector<double>& x,
                           std::vector<double>& y) const {
  const long blocks = static_cast<long>((x.size() + kCellsPerBlock - 1) / kCellsPerBlock);
  for_each_block(blocks, [&](long block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kCellsPerBlock;
    const std::size_t end = std::min(x.size(), begin + kCellsPerBlock);
    for (std::size_t i = begin; i < end; ++i) {
      const int first = particle_start_[i], last = particle_start_[i + 1];
      if (first == last) continue;
      double sx = 0, sy = 0;
      for (int k = first; k < last; ++k) {
        sx += particles[static_cast<std::size_t>(particle_[k])].x_um;
        sy += particles[static_cast<std::size_t>(particle_[k])].y_um;
      }
      x[i] = sx / (last - first);
      y[i] = sy / (last - first);
    }
  });
}

const CellStrainField& CellStrain::compute(const std::vector<Particle>& particles_now) {
  if (particles_now.size() != particle_.size())
    throw std::invalid_argument("cell strain: " + std::to_string(particles_now.size()) +
                                " particles given, expected the tissue's " + std::to_string(particle_.size()));
  std::copy(x0_.begin(), x0_.end(), x_.begin());  // (cells without particles do not move)
  std::copy(y0_.begin(), y0_.end(), y_.begin());
  centroids(particles_now, x_, y_);
  return compute_from_centroids(x_, y_);
}

const CellStrainField& CellStrain::compute_from_centroids(const std::vector<double>& x_um,
                                                          const std::vector<double>& y_um) {
  if (x_um.size() != x0_.size() || y_um.size() != x0_.size())
    throw std::invalid_argument("cell strain: positions of " + std::to_string(x_um.size()) + " and " +
                                std::to_string(y_um.size()) + " cells given, expected " +
                                std::to_string(x0_.size()));
  if (&x_um != &x_) std::copy(x_um.begin(), x_um.end(), x_.begin());
  if (&y_um != &y_) std::copy(y_um.begin(), y_um.end(), y_.begin());
  const long blocks = static_cast<long>((x0_.size() + kCellsPerBlock - 1) / kCellsPerBlock);
  for_each_block(blocks, [&](long block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kCellsPerBlock;
    const std::size_t end = std::min(x0_.size(), begin + kCellsPerBlock);
    for (std::size_t i = begin; i < end; ++i) strain_of_cell(i);
  });
  return field_;
}

// H = (sum (d - d0) d0^T) Y^-1, E = (H + H^T + H^T H) / 2 (header).
void CellStrain::strain_of_cell(std::size_t i) {
  if (std::isnan(Y_inv_xx_[i])) return;  // stays NaN
  const double ux = x_[i] - x0_[i], uy = y_[i] - y0_[i];
  double sxx = 0, sxy = 0, syx = 0, syy = 0;  // sum (u_j - u_i) d0^T
  for (int k = neighbour_start_[i]; k < neighbour_start_[i + 1]; ++k) {
    const auto j = static_cast<std::size_t>(neighbour_[k]);
    const double dx0 = x0_[j] - x0_[i], dy0 = y0_[j] - y0_[i];
    const double dux = (x_[j] - x0_[j]) - ux, duy = (y_[j] - y0_[j]) - uy;
    sxx += dux * dx0;
    sxy += dux * dy0;
    syx += duy * dx0;
    syy += duy * dy0;
  }
  const double a = Y_inv_xx_[i], b = Y_inv_xy_[i], d = Y_inv_yy_[i];
  const double Hxx = sxx * a + sxy * b, Hxy = sxx * b + sxy * d;
  const double Hyx = syx * a + syy * b, Hyy = syx * b + syy * d;
  const double Exx = Hxx + 0.5 * (Hxx * Hxx + Hyx * Hyx);
  const double Eyy = Hyy + 0.5 * (Hxy * Hxy + Hyy * Hyy);
  const double Exy = 0.5 * (Hxy + Hyx + Hxx * Hxy + Hyx * Hyy);
  field_.E_xx[i] = Exx;
  field_.E_yy[i] = Eyy;
  field_.E_xy[i] = Exy;
  field_.fibre_stretch[i] = std::sqrt(1 + 2 * Eyy);
  field_.max_shear[i] = std::hypot(0.5 * (Exx - Eyy), Exy);
}

}  // namespace fibrodem
