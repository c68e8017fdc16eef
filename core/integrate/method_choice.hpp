// solver.method "auto": the cheapest integrator, with its settings, for the
// APD90 accuracy a scene asks for (solver.accuracy), chosen from what the
// accuracy ladders measured (docs/topics/numerics.md#what-accuracy-costs):
// - a few cells (a single cell, a cell with its fibroblasts): CVODE, which is
//   cheapest at every error level there;
// - tissue: "adaptive", whose implicit coupling and one evaluation per step
//   beat both CVODE's Newton-Krylov solves and any fixed step.
// The tolerances come from the ladders' error against tolerance, with a margin.
#pragma once

#include <cstddef>
#include <string>

#include "integrate/solver_spec.hpp"

namespace fibrodem {

struct MethodChoice {
  SolverSpec solver;  // method, rtol, atol set; everything else as given
  std::string why;    // for run.log and summary.json
};

inline constexpr std::size_t kMostCellsForCvode = 16;

// `solver` has method "auto"; `cells` is the scene's cell count.
MethodChoice choose_method(const SolverSpec& solver, std::size_t cells);

}  // namespace fibrodem
