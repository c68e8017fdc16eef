// A cheap estimate, before a run, of the largest stable step of the explicit
// parts of a fixed-step scheme:
// - explicit coupling: forward Euler on C dV/dt = -L V needs dt < 2/lambda_max,
//   with the Gershgorin bound lambda_max <= max_i 2 sum_j D_ij / C_i;
// - gates under forward Euler: dy/dt = a + b y needs dt < 2/|b|; |b| = 1/tau is
//   probed over V from 10 mV below the initial potential to +60 mV, the other
//   states at their initial values
//   (Rush-Larsen integrates gates exactly and has no such limit).
// It is an estimate: the stiffness of concentrations and of V itself through
// the membrane conductance is not probed.
#pragma once

#include <limits>
#include <string>

#include "integrate/cell_system.hpp"

namespace fibrodem {

struct StabilityEstimate {
  double coupling_limit_ms = std::numeric_limits<double>::infinity();
  double gate_limit_ms = std::numeric_limits<double>::infinity();
  std::string fastest_gate;  // "model: state at V = ... mV"
  double limit_ms() const { return std::min(coupling_limit_ms, gate_limit_ms); }
};

StabilityEstimate estimate_explicit_stability(CellSystem& system, bool euler_gates, bool explicit_coupling);

}  // namespace fibrodem
