// Small inline accessors that let a model's per-cell code read like its paper
// while it runs over a structure-of-arrays block (see cell_model.hpp).
#pragma once

#include <cmath>
#include <cstddef>

#include "model/cell_model.hpp"

namespace fibrodem {

class CellAccess {
 public:
  CellAccess(const BlockView& block, std::size_t cell) : v_(block), c_(cell) {}

  double state(int k) const { return v_.y[k * v_.stride + c_]; }
  double input(int k) const { return v_.inputs[k * v_.stride + c_]; }
  double param(int k) const { return v_.params[k]; }

  // A state that is not a gate: dy/dt given directly.
  void rate(int k, double dydt) const {
    v_.a[k * v_.stride + c_] = dydt;
    v_.b[k * v_.stride + c_] = 0.0;
  }
  // A gate from its steady state and time constant: dy/dt = (y_inf - y)/tau.
  void gate_inf_tau(int k, double y_inf, double tau) const {
    v_.a[k * v_.stride + c_] = y_inf / tau;
    v_.b[k * v_.stride + c_] = -1.0 / tau;
  }
  // A gate from its opening and closing rates: dy/dt = alpha (1 - y) - beta y.
  void gate_alpha_beta(int k, double alpha, double beta) const {
    v_.a[k * v_.stride + c_] = alpha;
    v_.b[k * v_.stride + c_] = -(alpha + beta);
  }
  void output(int k, double value) const {
    if (v_.outputs != nullptr) v_.outputs[k * v_.stride + c_] = value;
  }

 private:
  const BlockView& v_;
  std::size_t c_;
};

}  // namespace fibrodem
