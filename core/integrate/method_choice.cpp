#include "integrate/method_choice.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace fibrodem {

MethodChoice choose_method(const SolverSpec& solver, std::size_t cells) {
  MethodChoice choice{solver, {}};
  const double accuracy = solver.accuracy_ms;
  if (cells <= kMostCellsForCvode) {
    // CVODE's APD90 error on the single cell and the cell pair: < 0.1 ms at
    // rtol 1e-3, ~0.02 ms at 1e-4 (docs/accuracy): rtol = accuracy / 500.
    choice.solver.method = "cvode";
    choice.solver.rtol = std::clamp(accuracy / 500, 1e-9, 1e-3);
    choice.solver.atol = 1e-2 * choice.solver.rtol;
    choice.why = fmt::format("{} cell(s) <= {}: CVODE, rtol {:.2g}, atol {:.2g} (solver.accuracy {} ms of APD90)",
                             cells, kMostCellsForCvode, choice.solver.rtol, choice.solver.atol, accuracy);
  } else {
    // The adaptive method's largest APD90 error over the cells of the Fig. 3
    // tissue: 0.05 ms at rtol = atol = 1e-2, 0.46 ms at 3e-2 (and ~tol^2
    // between): rtol = accuracy / 25, capped where it was measured.
    choice.solver.method = "adaptive";
    choice.solver.rtol = std::clamp(accuracy / 25, 1e-6, 3e-2);
    choice.solver.atol = choice.solver.rtol;
    choice.why = fmt::format("{} cells > {}: adaptive, rtol = atol = {:.2g} (solver.accuracy {} ms of APD90)",
                             cells, kMostCellsForCvode, choice.solver.rtol, accuracy);
  }
  return choice;
}

}  // namespace fibrodem
