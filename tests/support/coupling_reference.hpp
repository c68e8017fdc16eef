// The reference for the implicit gap-junction step: the system
// (C/dt + L) x = (C/dt) V built densely from a tissue's edges and solved by
// Eigen's dense LDLT (tests/coupling/test_coupling_cg.cpp, tests/coupling/test_mpi_coupling_cg.cpp).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem::test {

// L [nS] from the tissue's edges (seed paper eq. 4-5: D_m between two
// myocytes, D_f for a pair with a fibroblast).
inline Eigen::MatrixXd dense_laplacian(const Tissue& tissue, double D_m_nS, double D_f_nS) {
  const auto n = static_cast<Eigen::Index>(tissue.cell_count());
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [i, j] : tissue.cell_edges) {
    const bool both_myocytes = tissue.type[i] == CellType::myocyte && tissue.type[j] == CellType::myocyte;
    const double g = both_myocytes ? D_m_nS : D_f_nS;
    L(i, i) += g, L(j, j) += g, L(i, j) -= g, L(j, i) -= g;
  }
  return L;
}

// x = (C/dt + L)^-1 (C/dt) V by a dense LDLT.
inline std::vector<double> direct_solve(const Eigen::MatrixXd& L, const std::vector<double>& C,
                                        const std::vector<double>& V, double dt_ms) {
  const auto n = static_cast<Eigen::Index>(V.size());
  Eigen::MatrixXd A = L;
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    A(i, i) += C[static_cast<std::size_t>(i)] / dt_ms;
    b(i) = C[static_cast<std::size_t>(i)] / dt_ms * V[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd x = A.ldlt().solve(b);
  return {x.data(), x.data() + n};
}

inline double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double most = 0;
  for (std::size_t i = 0; i < a.size(); ++i) most = std::max(most, std::abs(a[i] - b[i]));
  return most;
}

}  // namespace fibrodem::test
