#include "run/state_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "io/csv_writer.hpp"
#include "run/simulation.hpp"

namespace fibrodem {
namespace {

// A blow-up at a step this many times below the stability estimate is
// blamed on the model: 10x leaves no doubt that an explicit scheme is stable
// there.
constexpr double kModelBlameFactor = 10;

std::string plugin_file(const PluginRegistry& registry, const Population& pop) {
  for (const auto& r : registry.loaded())
    if (r.name == pop.info().name) return r.file.string();
  return "plugin";
}

// "V = -80.1 mV, n = nan, ...": every state of local cell c.
std::string cell_states(const Population& pop, std::size_t c) {
  std::string s;
  for (std::size_t k = 0; k < pop.n_states(); ++k)
    s += (k ? ", " : "") + pop.info().states[k].name + " = " + format_number(pop.state(static_cast<int>(k), c)) +
         (pop.info().states[k].unit.empty() || pop.info().states[k].unit == "1" ? "" : " " + pop.info().states[k].unit);
  return s;
}

[[noreturn]] void blow_up(const CellSystem& system, double t, const Population& pop, std::size_t k, std::size_t c,
                          double value, const BlowUpContext& context) {
  const SolverSpec& solver = context.solver;
  const StabilityEstimate& stability = context.stability;
  std::ostringstream s;
  s << "blow-up at t = " << format_number(t) << " ms: cell "
    << system.numbering.tissue_cell(static_cast<std::size_t>(pop.cells[c])) << " ("
    << cell_type_name(pop.type) << ", model " << pop.info().name << "), state '" << pop.info().states[k].name
    << "' = " << format_number(value) << " " << pop.info().states[k].unit << ", expected within ["
    << format_number(pop.info().states[k].lower) << ", " << format_number(pop.info().states[k].upper)
    << "]";
  // A step far below the estimated stability limit (or with none: gates by
  // Rush-Larsen, no explicit coupling) is not what went wrong: the model is.
  const double dt = solver.dt_ms;
  if (solver.fixed_step() && dt * kModelBlameFactor <= stability.limit_ms()) {
    s << "; the step (solver.dt_ms = " << format_number(dt) << " ms) is "
      << (std::isfinite(stability.limit_ms())
              ? fmt::format("{:.3g}x below the estimated explicit stability limit ({:.3g} ms)",
                            stability.limit_ms() / dt, stability.limit_ms())
              : std::string("not limited by any explicit stability estimate (gates by Rush-Larsen, no explicit "
                            "coupling)"))
      << ", so the model is the likely cause, not the step: model " << pop.info().name << " ("
      << plugin_file(context.registry, pop) << ") took '" << pop.info().states[k].name
      << "' there. The cell's states after that step (each finite one "
      << "is its last finite value; a non-finite one had a non-finite rate in that step): " << cell_states(pop, c)
      << ". Check the model with: fibrodem check-plugin " << pop.info().name;
  } else if (solver.fixed_step()) {
    s << "; " << context.integrator.describe() << " may be unstable here";
    if (std::isfinite(stability.limit_ms()))
      s << fmt::format(" (estimated explicit stability limit {:.3g} ms, set by {}; a stable step: solver.dt_ms <= {:.3g})",
                       stability.limit_ms(),
                       stability.coupling_limit_ms <= stability.gate_limit_ms ? std::string("the coupling")
                                                                              : stability.fastest_gate,
                       0.5 * stability.limit_ms());
    s << ": try a smaller solver.dt_ms"
      << (system.coupler && !system.implicit_coupling ? ", coupling.scheme \"implicit\"" : "")
      << " or solver.method \"cvode\"";
  }
  throw BlowUpError(s.str());
}

}  // namespace

// The range is widened by round-off (1e-6 relative) and, for CVODE, by its
// error tolerance: a gate at 1 + 1e-6 after a BDF step at rtol 1e-6 is not a
// blow-up. (The fixed-step integrators check the states as they update them;
// check_states then scans them only to name the state that left its range.)
void set_state_limits(CellSystem& system, const SolverSpec& solver) {
  const bool cvode = solver.method == "cvode";
  // Ten times CVODE's local error bound rtol |y| + atol at the bound.
  auto slack = [&](double bound) {
    const double scale = std::max(1.0, std::abs(bound));
    return std::max(1e-6 * scale, cvode ? 10 * (solver.rtol * scale + solver.atol) : 0.0);
  };
  system.for_each_population([&](Population& pop) {
    pop.lower_limit.clear();
    pop.upper_limit.clear();
    for (const StateInfo& state : pop.info().states) {
      pop.lower_limit.push_back(state.lower - slack(state.lower));
      pop.upper_limit.push_back(state.upper + slack(state.upper));
    }
  });
}

void check_states(CellSystem& system, double t, const BlowUpContext& context) {
  if (system.states_checked && system.states_in_limits) return;
  system.for_each_population([&](const Population& pop) {
    const std::size_t n = pop.size();
    for (std::size_t k = 0; k < pop.n_states(); ++k) {
      const double* y = pop.y.data() + k * n;
      for (std::size_t c = 0; c < n; ++c)
        if (!(y[c] >= pop.lower_limit[k] && y[c] <= pop.upper_limit[k]))
          blow_up(system, t, pop, k, c, y[c], context);
    }
  });
}

}  // namespace fibrodem
