// solver.method "adaptive": error-controlled second-order Rush-Larsen for
// tissue.
//
// Each step is the exponential midpoint scheme (gates, and any other state
// whose model gives it a slope b, are taken exponentially) of FixedStepIntegrator's
// rush_larsen2 (Perego & Veneziani 2009, ETNA 35:234): a first-order
// Rush-Larsen half step, the linear forms a + b y re-evaluated at the
// midpoint, then the full step from the start with the midpoint's a, b. The
// first-order full step from the start (the same first evaluation, one more
// update) is the embedded estimate: |y2 - y1| is the local error of the
// first-order step, O(h^2), and the second-order result is kept (local
// extrapolation). A step is accepted when, for every cell and state,
//   |y2 - y1| <= rtol |y2| + atol * scale,
// scale = 1 for gates and each other state's magnitude at the start of the run
// (so that V, in mV, and Ca_i, in mM, are held to the same relative accuracy).
// Rejected steps are retried from the saved states; StepController (PI)
// chooses the next step.
//
// Coupling never caps the step: the gap-junction term of V, -K V with
// K = C^-1 L (seed paper eq. 4-5), is taken implicitly. With theta = h/2,
//   midpoint:  (I + theta K) V_half = V0 + theta F0             (backward Euler)
//   full step: (I + theta K) V1 = (I - theta K) V0 + h F_half    (Crank-Nicolson
//              on the coupling, the membrane term F at the midpoint)
// and the first-order companion of V1 is 2 V_half - V0 (Crank-Nicolson with
// F taken at the start), so V1 - V_hat = h (I + theta K)^-1 (F_half - F0).
// Both solves share one matrix, C + theta L (sparse LDLT, kept per step size:
// steps are powers of two times kStepQuantum_ms, so a run needs a dozen).
// Without coupling V is advanced like any other non-gate state.
//
// Steps land exactly on stimulus edges (restarting the controller with a small
// step there, so that a 0.1 ms pulse is never stepped over), on sample times
// and at the end.
#pragma once

#include <string>
#include <vector>

#include "integrate/integrator.hpp"
#include "integrate/step_controller.hpp"

namespace fibrodem {

class AdaptiveIntegrator final : public Integrator {
 public:
  explicit AdaptiveIntegrator(const SolverSpec& solver);
  void advance(CellSystem& system, double t_start_ms, double t_end_ms, StepObserver& observer) override;
  std::string describe() const override;
  std::string report() const override { return histogram_.describe(); }

  static constexpr double kFirstStep_ms = 0.01;  // at the start and after each stimulus edge
  static constexpr double kMinStep_ms = 1e-7;     // below it, a step that still fails stops the run
  // Steps are 2^k times this (k an integer; it lands on every stimulus edge
  // and sample time that is a multiple of a power of two of it, such as
  // 0.5 ms and 100 ms); only a step to an off-grid stop is not.
  static constexpr double kStepQuantum_ms = 1.0 / 1024;

 private:
  // Per population: the states at the step's start, the first-order full
  // step, and per state the scale of its absolute tolerance.
  struct Buffers {
    const Population* pop = nullptr;
    std::vector<double> start, first_order, scale;
  };
  void prepare(CellSystem& system);
  // One trial step from t over h: the error in tolerances (inf if a state
  // left its range or is NaN). The populations then hold the new states.
  double try_step(CellSystem& system, double t, double h);
  void restore();
  static double on_grid(double h_ms);  // the states at the step's start, back in place
  Buffers& buffers_of(const Population& pop);
  [[noreturn]] void fail(CellSystem& system, double t, double h, double err);

  double rtol_, atol_, max_step_ms_;
  StepController controller_{1};
  StepHistogram histogram_;
  std::vector<Buffers> buffers_;
  // Coupled V, per global cell: the right-hand sides of the two solves (then
  // their solutions) and the gap-junction current at the step's start.
  std::vector<double> v_half_, v_full_, gap_pA_;
};

}  // namespace fibrodem
