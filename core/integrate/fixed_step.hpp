// Fixed-step integrators:
// - forward Euler for every state (the seed paper's scheme);
// - Rush-Larsen (Rush & Larsen 1978, IEEE TBME 25:389): each gate advanced
//   exactly over the step from its linear form dy/dt = a + b*y,
//       y' = y_inf + (y - y_inf) * exp(b*dt),  y_inf = -a/b,
//   all other states by forward Euler (first order);
// - second-order Rush-Larsen (the exponential midpoint scheme of Perego &
//   Veneziani 2009, ETNA 35:234; cf. Sundnes et al. 2009): a half step of
//   Rush-Larsen, the linear forms re-evaluated at the midpoint, then the full
//   step from the start with the midpoint's a, b (gates exactly, other states
//   by the explicit midpoint rule). Two evaluations per step.
// Coupling is either explicit (its current is part of i_ext, at the same
// stage as the cell models) or split off and advanced by backward Euler after
// the cell step (Godunov splitting, first order in dt).
#pragma once

#include "integrate/integrator.hpp"

namespace fibrodem {

class FixedStepIntegrator final : public Integrator {
 public:
  enum class Rule { euler, rush_larsen, rush_larsen2 };
  FixedStepIntegrator(Rule rule, double dt_ms) : rule_(rule), dt_ms_(dt_ms) {}

  void advance(CellSystem& system, double t_start_ms, double t_end_ms,
               StepObserver& observer) override;
  std::string describe() const override;

  // Advances every state of a population over dt with its present a, b.
  void update_states(Population& pop, double dt_ms) const { update_from(pop, pop.y, pop.y, dt_ms); }
  // Advances one block of a population over dt from the a, b of its own view
  // (Population::evaluate with an AfterBlock); false if a new value left the
  // population's limits (lower_limit, upper_limit).
  bool update_view(const Population& pop, const BlockView& block, double dt_ms) const;

  // The split coupling solve's tolerance on V [mV] (coupling.scheme
  // "implicit"): these methods have no error control to tie it to, so it is
  // far below any fixed step's own error in V (>= 1e-4 mV at dt 0.001 ms).
  static constexpr double kCouplingSolveTolerance_mV = 1e-7;

 private:
  // Advances from the states `from` (gates exactly, others by Euler) with the
  // present a, b; the non-gate slope a + b*y is taken at `slope_at` (the
  // midpoint, for the second-order rule). Either may be the population's own y.
  void update_from(Population& pop, const std::vector<double>& from, const std::vector<double>& slope_at,
                   double dt_ms) const;
  // The same for the cells [begin, end) only; false if a new value left the
  // population's limits.
  bool update_block(Population& pop, const std::vector<double>& from, const std::vector<double>& slope_at,
                    std::size_t begin, std::size_t end, double dt_ms) const;
  // One step; shows the new potentials to `voltages_to` (if not null) on the step's threads.
  void step(CellSystem& system, double t, double t_next, StepObserver* voltages_to);
  void add_rush_larsen_tables(CellSystem& system) const;

  Rule rule_;
  double dt_ms_;
  // rush_larsen2, per population: states at the step's start and midpoint.
  std::vector<std::vector<double>> start_, midpoint_;
};

}  // namespace fibrodem
