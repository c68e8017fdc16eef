// A Coupler computes the currents that flow between cells (seed paper eq. 4-5)
// and can advance the coupling alone implicitly, so that strong coupling stays
// stable at the step the cell models need (operator splitting).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace fibrodem {

class Coupler {
 public:
  virtual ~Coupler() = default;
  // Adds the current into each cell [pA, + depolarising] for potentials V [mV].
  virtual void add_current(const double* V_mV, double* i_ext_pA) const = 0;
  // The current into each of `count` cells [pA], written to current_pA[k] for
  // cell cells[k] (one call per block of cells, into the block's own array:
  // threads on other blocks write elsewhere; the same sums as add_current).
  virtual void current_into(const double* V_mV, const int* cells, std::size_t count, double* current_pA) const = 0;
  // Advances C dV/dt = I_gap(V) alone over dt by backward Euler, in place,
  // to within tolerance_mV of the exact backward-Euler potentials (max norm).
  virtual void implicit_step(double* V_mV, double dt_ms, double tolerance_mV) = 0;
  // The next implicit_step starts afresh, from its input alone: called where
  // an integrator starts (a run resumed from a checkpoint starts there too,
  // so it must not depend on solves before it).
  virtual void restart_implicit() {}
  // How the implicit steps went ("" if there is nothing to say).
  virtual std::string describe_solves() const { return {}; }
  // Gershgorin bound on the fastest coupling rate |lambda| [1/ms]: forward
  // Euler on the coupling is stable for dt < 2 / rate.
  virtual double max_rate_per_ms() const = 0;
  // Each cell's total junctional conductance sum_j D_ij [nS] (the diagonal of
  // the coupling's Laplacian), e.g. for a preconditioner.
  virtual std::vector<double> total_conductance_nS() const = 0;
};

}  // namespace fibrodem
