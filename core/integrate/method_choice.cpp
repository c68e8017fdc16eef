#include "integrate/method_choice.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace fibrodem {

namespace {

// The adaptive method's tolerance (rtol = atol) for an APD90 accuracy asked.
// Measured where a tolerance's error is largest of the ladder scenes: the
// Fig. 3 in-series EP tissue narrowed to a 0.58 x 6.27 mm strip
// (examples/fig3_in_series_ep.json --set tissue.width_mm=0.58 --set
// duration_ms=400: 1518 cells, fibroblasts included, V sampled every
// 0.5 ms), largest APD90 error over the cells against adaptive at tol 3e-5:
//   tol    1e-4    0.001  0.005  0.01  0.02  0.03  0.04  0.06  0.1
//   error  0.0078  0.029  0.086  0.14  0.23  0.31  0.50  0.37  0.81 ms
// and on the whole Fig. 3 tissue (docs/accuracy/fig3_in_series_ep, against
// CVODE at rtol 1e-6, which CVODE at 1e-5 matches to 0.07 ms):
//   tol    0.001   0.003  0.01  0.03  0.06  0.1
//   error  0.094   0.12   0.21  0.37  0.41  0.62 ms
// The error is not monotone in the tolerance (0.04 gives more than 0.06 on
// the strip), so tolerances are not interpolated: an accuracy takes the
// tolerance of the largest rung not above it, whose error was within the
// rung's accuracy on both, and within 2x below it at 1, 0.5 and 0.1 ms on
// the larger of the two.
struct TissueRung {
  double accuracy_ms, tol;
};
// At the rung of 0.01 ms the strand (docs/accuracy/strand_colman, against
// CVODE at rtol 1e-9) gave 0.0083 ms at tol 1e-4, and 0.011 ms at 2e-4.
constexpr TissueRung kTissueRungs[] = {{0.01, 1e-4}, {0.1, 1e-3}, {0.25, 1e-2}, {0.5, 6e-2}, {1, 1e-1}};

// Below the first rung, tol in proportion to the accuracy squared (no rung
// was measured there; the error falls no faster than the tolerance
// between 1e-3 and 1e-4), down to 1e-6 (from 1e-3 ms; solver.accuracy goes
// down to 1e-4 ms). From the last rung up, the last: 0.1 is the loosest rtol
// the method takes (solver_spec.cpp).
double adaptive_tolerance(double accuracy_ms) {
  const TissueRung& first = kTissueRungs[0];
  if (accuracy_ms < first.accuracy_ms) {
    const double ratio = accuracy_ms / first.accuracy_ms;
    return std::max(first.tol * ratio * ratio, 1e-6);
  }
  double tol = first.tol;
  for (const TissueRung& rung : kTissueRungs)
    if (rung.accuracy_ms <= accuracy_ms) tol = rung.tol;
  return tol;
}

}  // namespace

MethodChoice choose_method(const SolverSpec& solver, std::size_t cells) {
  MethodChoice choice{solver, {}};
  const double accuracy = solver.accuracy_ms;
  if (cells <= kMostCellsForCvode) {
    // CVODE's APD90 error on the single cell and the cell pair
    // (docs/accuracy): 0.058 and 0.088 ms at rtol 1e-3, 0.004 and 0.024 ms
    // at 1e-4: rtol = accuracy / 500. Capped at 1e-3: looser, the error is
    // erratic (rtol 5e-3: 0.07 and 0.69 ms; 3e-3: 0.002 and 0.07 ms; 1e-2:
    // 0.13 and 0.57 ms, measured on the same two ladder scenes with
    // `--methods cvode --rtol 1e-2,5e-3,3e-3`) and saves few steps (293
    // against 428 on the single cell).
    choice.solver.method = "cvode";
    choice.solver.rtol = std::clamp(accuracy / 500, 1e-9, 1e-3);
    choice.solver.atol = 1e-2 * choice.solver.rtol;
    choice.why = fmt::format("{} cell(s) <= {}: CVODE, rtol {:.2g}, atol {:.2g} (solver.accuracy {} ms of APD90)",
                             cells, kMostCellsForCvode, choice.solver.rtol, choice.solver.atol, accuracy);
  } else {
    choice.solver.method = "adaptive";
    choice.solver.rtol = adaptive_tolerance(accuracy);
    choice.solver.atol = choice.solver.rtol;
    choice.why = fmt::format("{} cells > {}: adaptive, rtol = atol = {:.2g} (solver.accuracy {} ms of APD90)",
                             cells, kMostCellsForCvode, choice.solver.rtol, accuracy);
  }
  return choice;
}

}  // namespace fibrodem
