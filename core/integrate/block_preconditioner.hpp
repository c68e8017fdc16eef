// Block-diagonal (per-cell) preconditioner for CVODE's Krylov solver at tissue
// scale: P = I - gamma J_cell for each cell, J_cell the Jacobian of the cell's
// own model(s) by finite differences plus the diagonal of its coupling (the
// gap-junction current's -sum_j D_ij / C_i on dV/dt). Cells are independent
// through everything but V, so one evaluation of the whole system per state
// index gives column k of every cell's block at once (perturbing state k of
// all cells together; the coupling terms this mixes in cancel for V).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <vector>

namespace fibrodem {

class BlockPreconditioner {
 public:
  // offsets/sizes: each cell's block in the packed state vector;
  // coupling_diag: -sum_j D_ij / C_i [1/ms] at the row of each cell's V (or 0).
  BlockPreconditioner(std::vector<std::size_t> offsets, std::vector<std::size_t> sizes,
                      std::vector<std::size_t> voltage_rows, std::vector<double> coupling_diag);

  // rhs(y, f) evaluates the system's right-hand side.
  using Rhs = std::function<bool(const double* y, double* f)>;
  // Recomputes the Jacobian blocks at (y, fy) if !reuse, then factors I - gamma J.
  bool setup(const double* y, const double* fy, bool reuse, double gamma, const Rhs& rhs);
  // z = P^-1 r.
  void solve(const double* r, double* z) const;

 private:
  std::vector<std::size_t> offsets_, sizes_, voltage_rows_;
  std::vector<double> coupling_diag_;
  std::size_t total_ = 0, widest_ = 0;
  std::vector<Eigen::MatrixXd> jacobians_;
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXd>> factors_;
  std::vector<double> perturbed_, f_perturbed_, step_;
};

}  // namespace fibrodem
