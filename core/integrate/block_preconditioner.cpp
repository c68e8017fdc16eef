#include "integrate/block_preconditioner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrodem {

BlockPreconditioner::BlockPreconditioner(std::vector<std::size_t> offsets, std::vector<std::size_t> sizes,
                                         std::vector<std::size_t> voltage_rows, std::vector<double> coupling_diag)
    : offsets_(std::move(offsets)), sizes_(std::move(sizes)), voltage_rows_(std::move(voltage_rows)),
      coupling_diag_(std::move(coupling_diag)) {
  for (std::size_t c = 0; c < sizes_.size(); ++c) {
    total_ = std::max(total_, offsets_[c] + sizes_[c]);
    widest_ = std::max(widest_, sizes_[c]);
    jacobians_.emplace_back(Eigen::MatrixXd::Zero(sizes_[c], sizes_[c]));
  }
  factors_.resize(sizes_.size());
  perturbed_.resize(total_);
  f_perturbed_.resize(total_);
  step_.resize(total_);
}

bool BlockPreconditioner::setup(const double* y, const double* fy, bool reuse, double gamma, const Rhs& rhs) {
  if (!reuse) {
    const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
    for (std::size_t k = 0; k < widest_; ++k) {
      std::copy(y, y + total_, perturbed_.begin());
      for (std::size_t c = 0; c < sizes_.size(); ++c) {
        if (k >= sizes_[c]) continue;
        const std::size_t i = offsets_[c] + k;
        step_[i] = root_eps * std::max(std::abs(y[i]), 1e-6);
        perturbed_[i] += step_[i];
      }
      if (!rhs(perturbed_.data(), f_perturbed_.data())) return false;
      for (std::size_t c = 0; c < sizes_.size(); ++c) {
        if (k >= sizes_[c]) continue;
        const std::size_t column = offsets_[c] + k;
        for (std::size_t row = 0; row < sizes_[c]; ++row) {
          const std::size_t i = offsets_[c] + row;
          jacobians_[c](static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(k)) =
              (f_perturbed_[i] - fy[i]) / step_[column];
        }
      }
    }
    // Perturbing every V together cancels the coupling; put its diagonal back.
    for (std::size_t c = 0; c < sizes_.size(); ++c) {
      const auto v = static_cast<Eigen::Index>(voltage_rows_[c] - offsets_[c]);
      jacobians_[c](v, v) += coupling_diag_[c];
    }
  }
  for (std::size_t c = 0; c < sizes_.size(); ++c) {
    const auto n = static_cast<Eigen::Index>(sizes_[c]);
    factors_[c].compute(Eigen::MatrixXd::Identity(n, n) - gamma * jacobians_[c]);
  }
  return true;
}

void BlockPreconditioner::solve(const double* r, double* z) const {
  for (std::size_t c = 0; c < sizes_.size(); ++c) {
    const auto n = static_cast<Eigen::Index>(sizes_[c]);
    Eigen::Map<const Eigen::VectorXd> rc(r + offsets_[c], n);
    Eigen::Map<Eigen::VectorXd> zc(z + offsets_[c], n);
    zc = factors_[c].solve(rc);
  }
}

}  // namespace fibrodem
