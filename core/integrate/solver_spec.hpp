// The manifest's `solver` section: the integration method of the cells and
// its settings, and its reader. integrate/integrator.hpp makes the integrator
// it names.
#pragma once

#include <optional>
#include <string>

#include "tissue/cell_partition.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

struct SolverSpec {
  // auto (the default) | euler | rush_larsen | rush_larsen2 | cvode | adaptive.
  // auto: the simulation picks the method and its settings for accuracy_ms
  // (integrate/method_choice.hpp) once the tissue is built.
  std::string method = "auto";
  double accuracy_ms = 0.5;            // auto ("accuracy" in the manifest): the APD90 error [ms] to aim below
  double dt_ms = 0.01;                 // euler, rush_larsen, rush_larsen2
  // cvode: CVODE's tolerances. adaptive: each state's local error per step
  // stays below rtol |y| + atol * scale (scale: 1 for gates, else the state's
  // magnitude at the start), with these defaults when unset.
  double rtol = 1e-6, atol = 1e-8;
  static constexpr double kAdaptiveRtol = 1e-2, kAdaptiveAtol = 1e-2;
  double max_step_ms = 0;              // cvode; 0: no cap (it stops at every stimulus edge anyway)
  std::string linear_solver = "auto";  // cvode: auto | dense | band | krylov
  // Threads over blocks of cells: -1 (the default, "auto"): every core when
  // the scene is large enough to gain, else 1; 0: every core; results do not
  // depend on it.
  int threads = -1;
  // How a tissue split over MPI ranks is cut ("rcb" | "scotch").
  PartitionMethod partition = PartitionMethod::rcb;
  // Rates (and, for rush_larsen, exp(b dt)) of voltage_only gates from tables
  // in V (linear, 0.05 mV). Unset: on for the fixed-step methods (their APD90
  // moves < 0.001 ms, docs/topics/numerics.md#lookup-tables), off for CVODE (a table makes
  // the right-hand side only piecewise smooth).
  std::optional<bool> lookup_tables;
  bool use_lookup_tables() const { return lookup_tables.value_or(method != "cvode"); }
  bool fixed_step() const { return fixed_step(method); }
  static bool fixed_step(const std::string& method);  // integrate/integrator.cpp, from the registry
  bool simd = true;                    // false: models one cell at a time in double (the reference path)
};

// Reads the manifest's `solver` object (ManifestError naming the JSON path).
SolverSpec read_solver_spec(JsonReader solver);

}  // namespace fibrodem
