// SUNDIALS CVODE (BDF + Newton) over the coupled system of a small tissue:
// every cell's states and the gap-junction currents between them in one ODE
// system, with a dense or banded direct linear solver (finite-difference
// Jacobian). The stiff, accurate reference.
//
// Hygiene (Myokit issue #67, Chaste AbstractCvodeCell): CVODE stops exactly at
// every stimulus edge (tstop) and is re-initialised there, so it cannot step
// over a stimulus; between edges its step is free (capped only by a user's
// max_step_ms). Within an interval between edges the stimulus is constant (its
// value at the interval's middle).
// States are packed cell by cell, so a strand gives a narrow band.
#pragma once

#include <string>
#include <vector>

#include "integrate/integrator.hpp"

namespace fibrodem {

class CvodeIntegrator final : public Integrator {
 public:
  explicit CvodeIntegrator(const SolverSpec& spec) : spec_(spec) {}
  void advance(CellSystem& system, double t_start_ms, double t_end_ms,
               StepObserver& observer) override;
  std::string describe() const override;

 private:
  SolverSpec spec_;
  std::string linear_solver_used_;
  // CVODE's work in the last advance(), for the run log.
  struct Work {
    long steps = 0, rhs_evaluations = 0, jacobians = 0;
  } work_;
};

}  // namespace fibrodem
