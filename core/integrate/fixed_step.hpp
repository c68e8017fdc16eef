// Fixed-step integrators: forward Euler for every state (the seed paper's
// scheme), or Rush-Larsen (Rush & Larsen 1978, IEEE TBME 25:389): each gate
// advanced exactly over the step from its linear form dy/dt = a + b*y,
//     y' = y_inf + (y - y_inf) * exp(b*dt),  y_inf = -a/b,
// all other states by forward Euler. Coupling is either explicit (its current
// is part of i_ext) or split off and advanced by backward Euler after the
// cell step (Godunov splitting, first order).
#pragma once

#include "integrate/integrator.hpp"

namespace fibrodem {

class FixedStepIntegrator final : public Integrator {
 public:
  enum class Rule { euler, rush_larsen };
  FixedStepIntegrator(Rule rule, double dt_ms) : rule_(rule), dt_ms_(dt_ms) {}

  void advance(CellSystem& system, double t_start_ms, double t_end_ms,
               StepObserver& observer) override;
  std::string describe() const override;

  // One step of every population from its current a, b.
  void update_states(Population& pop, double dt_ms) const;

 private:
  Rule rule_;
  double dt_ms_;
};

}  // namespace fibrodem
