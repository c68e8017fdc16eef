// solver.method "adaptive": error-controlled second-order Rush-Larsen for
// tissue, with the gap-junction coupling implicit.
//
// States: gates, and any other state whose model gives it a slope b
// (Cells::stiff_rate), are advanced exponentially from their linear form
// dy/dt = a + b y over the step, y' = y_inf + (y - y_inf) exp(b h); the rest
// by y' = y + h (a + b y). Second order comes from taking the linear form at
// the step's middle (the exponential midpoint scheme of Perego & Veneziani
// 2009, ETNA 35:234), found in one of two ways:
// - extrapolated (one model evaluation per step): a_mid = a_n + omega (a_n -
//   a_{n-1}), omega = h / (2 h_{n-1}), likewise b (an exponential
//   Adams-Bashforth 2 step);
// - evaluated (two evaluations: a first-order half step, then the forms at
//   the midpoint), where there is no history to extrapolate from: at the
//   start, after a stimulus edge (the right-hand side jumps), after a
//   rejected step.
// The potential: with K = C^-1 L the coupling (seed paper eq. 4-5), F the
// membrane term (all of dV/dt but the coupling), theta = h/2,
//   (I + theta K) V1 = (I - theta K) V0 + h F_mid
// (Crank-Nicolson on the coupling, CNAB2 with F_mid extrapolated; with F_mid
// evaluated, V_half from (I + theta K) V_half = V0 + theta F0). So the
// coupling never caps the step. The coupler solves it by conjugate gradients
// to within kSolveToleranceFraction of V's absolute tolerance (max norm), so
// that the solve's error is a thousandth of what the step control allows.
//
// Error: the step with the start's own linear forms (a_n, b_n; F0) is first
// order, and its difference to the second-order step estimates the local
// error of the first; the second-order result is kept (local extrapolation).
// A step is accepted when, for every cell and state,
//   |y2 - y1| <= rtol |y2| + atol * scale,
// scale = 1 for gates and each other state's magnitude at the start of the run
// (so that V, in mV, and Ca_i, in mM, are held to the same relative accuracy).
// For V in the extrapolated step, h |F_mid - F0| bounds the difference
// ((I + theta K)^-1 has max norm 1). Rejected steps are retried from the saved
// states with the evaluated midpoint (the extrapolated step overwrites its
// history with its start's linear forms, so that a state needs three arrays:
// the saved start, a and b); StepController (PI) chooses the next step.
//
// Steps land exactly on stimulus edges (restarting the controller with a
// small step there, so that a 0.1 ms pulse is never stepped over), on sample
// times and at the end.
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
  std::string report() const override;

  static constexpr double kFirstStep_ms = 0.01;  // at the start and after each stimulus edge
  static constexpr double kMinStep_ms = 1e-7;     // below it, a step that still fails stops the run
  // Steps are 1 or 1.5 times 2^k times this (k an integer), so that they tile
  // the stretch to every stimulus edge and sample time on the quantum's grid
  // (such as 0.5 ms or 100.25 ms); only a step to an off-grid stop is not.
  static constexpr double kStepQuantum_ms = 1.0 / 1024;
  // The coupling solve's tolerance on V [mV]: this fraction of the smallest
  // absolute tolerance of a coupled potential (atol x its scale), but not
  // below kSmallestSolveTolerance_mV, near what rounding lets CG resolve on
  // potentials of ~100 mV (an atol below ~1e-8 would otherwise ask for less).
  static constexpr double kSolveToleranceFraction = 1e-3;
  static constexpr double kSmallestSolveTolerance_mV = 1e-9;
  // From this rtol up (a population's: myofilaments' below), the last
  // step's linear forms are kept in float, which
  // halves the integrator's largest arrays (208 of its 648 bytes a colman
  // cell). Rounding a form to float moves it by at most 2^-24 (6e-8) of
  // itself; the extrapolated midpoint takes omega = h / (2 h_prev) of that
  // (0.5 at a steady step), so the state it sets (a gate's -a/b, or y + h a
  // by h a) moves by about 3e-8 of itself: 300x below the smallest tolerance
  // kept in float. The first-order companion, built from them too, feeds
  // only the estimate. Below it, double: the tightest runs keep their bits.
  static constexpr double kFloatHistoryRtol = 1e-5;
  // Myofilament states are held to this fraction of rtol and atol. The
  // tolerances are chosen for the potential's accuracy (method_choice.cpp),
  // and a myofilament model's states are out of their scale: Rice's
  // cross-bridge fractions (gates, atol absolute) sit at 1e-7 to 1e-2, and
  // its SL (relative to 1.9 um) moves by a few per cent. At auto's tolerance
  // on the Fig. 3 in-series EM scene (0.06) they gave peak eps_xx, eps_yy
  // 1.9 % and 2.7 % off a reference (adaptive at 1e-4, which Rush-Larsen
  // 0.01 ms matches to 1e-5), and the cells' SL rang by ~1e-3 at rest. At
  // 0.01 x: 0.18 % and 0.17 %, the tissue at rest until the stimulus, 1.3x
  // the steps; 0.1 x: 0.33 % and 0.50 %; 0.001 x: 0.10 %, 3.3x the steps.
  static constexpr double kMyofilamentToleranceFactor = 0.01;
  // A population's rtol, and whether its history is kept in float.
  static double population_rtol(double rtol, bool myofilament) {
    return myofilament ? kMyofilamentToleranceFactor * rtol : rtol;
  }
  static bool float_history(double population_rtol) { return population_rtol >= kFloatHistoryRtol; }

 private:
  // Per population: the states at the step's start, its relative tolerance
  // (whether its history is kept in float: rtol >= kFloatHistoryRtol), and
  // per state the scale of its absolute tolerance.
  struct Buffers {
    Population* pop = nullptr;
    double rtol = 0;
    bool float_history = false;
    std::vector<double> start, scale;
    // The first-order full step: filled only while fail() looks for the
    // worst state (a step's error is taken as it is computed).
    std::vector<double> first_order;
    // Linear forms a, b at the last accepted step's start; a step reads them,
    // then writes its own start's in their place. Kept only for the states
    // with form_row >= 0 (row form_row of a_last, b_last): a coupled
    // potential has F_last instead. In float (a_last_f, b_last_f) when
    // float_history, else in double.
    std::vector<double> a_last, b_last;
    std::vector<float> a_last_f, b_last_f;
    std::vector<int> form_row;
    // A coupled potential, per local cell (each block writes its own stretch):
    // the membrane term F at the last accepted step's start (the solves'
    // right-hand sides are written straight into v_global_).
    std::vector<double> F_last;
  };
  void prepare(CellSystem& system);
  // One trial step from t over h: the error in tolerances (inf if a state
  // left its range or is NaN). The populations then hold the new states.
  double try_step(CellSystem& system, double t, double h);
  double midpoint_step(CellSystem& system, double t, double h);      // two evaluations
  double extrapolated_step(CellSystem& system, double t, double h);  // one evaluation, needs history_
  double solve_potential(CellSystem& system, double theta, double error, bool with_companion);
  // Solves (I + theta K) V = rhs in place, rhs in v_global_.
  void solve(CellSystem& system, double theta);
  void accept(double h);
  template <class EachRow, class Potential>
  void for_rows(Population& pop, const BlockView& block, bool coupled, EachRow&& each_row, Potential&& potential);
  void restore();
  static double on_grid(double h_ms);
  double next_after_accepted(double step_ms, double wanted_ms, double err);
  Buffers& buffers_of(const Population& pop);
  [[noreturn]] void fail(CellSystem& system, double t, double h, double err);

  double rtol_, atol_, max_step_ms_;
  // Safety 0.7: the controller settles at an error estimate of ~0.09 of the
  // tolerance (step_controller.hpp), not at H&W's 0.5 (fac 0.9). With the
  // second-order result kept, the error delivered for a tolerance depends on
  // where the controller settles: at the default tolerances (0.01) the
  // 100-beat Na_i drift of a courtemanche cell strays 4 % from CVODE's at
  // fac 0.9, 2 % at 0.8, < 1 % at 0.7 (tests/integrate/test_hard_cases.cpp holds it to
  // 1 %). solver.accuracy's tolerances (method_choice.cpp) are measured with it.
  static constexpr double kControllerSafety = 0.7;
  StepController controller_{1, kControllerSafety};
  StepHistogram histogram_;
  std::vector<Buffers> buffers_;
  // Coupled V, per held cell: the right-hand side of a solve, then its solution.
  std::vector<double> v_global_;
  double solve_tolerance_mV_ = 0;
  std::string coupling_report_;  // the coupler's, at the end of the last advance
  bool history_ = false;  // the last step's linear forms are valid to extrapolate from
  double h_prev_ = 0;
};

}  // namespace fibrodem
