// The cells' states within their physical ranges (each model's StateInfo
// lower and upper): the limits, set once at set-up, and the check after each
// step. A state outside its range, or NaN/Inf, stops the run with a
// BlowUpError that says where, and whether the step or the model is the
// likely cause.
#pragma once

#include "integrate/cell_system.hpp"
#include "integrate/integrator.hpp"
#include "integrate/stability.hpp"
#include "model/plugin_registry.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// Each population's lower_limit and upper_limit: the states' ranges widened
// by round-off and, for CVODE, by its error tolerance.
void set_state_limits(CellSystem& system, const SolverSpec& solver);

// What a blow-up's message draws on to blame the step or the model.
struct BlowUpContext {
  const SolverSpec& solver;
  const StabilityEstimate& stability;
  const PluginRegistry& registry;
  const Integrator& integrator;
};

// Throws BlowUpError (run/simulation.hpp) naming the first state found
// outside its limits at time t_ms, unless the integrator has checked them all.
void check_states(CellSystem& system, double t_ms, const BlowUpContext& context);

}  // namespace fibrodem
