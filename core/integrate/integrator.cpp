#include "integrate/integrator.hpp"

#include "integrate/adaptive.hpp"
#include "integrate/cvode_integrator.hpp"
#include "integrate/fixed_step.hpp"

#include <stdexcept>

namespace fibrodem {

namespace {
template <FixedStepIntegrator::Rule rule>
std::unique_ptr<Integrator> make_fixed_step(const SolverSpec& solver) {
  return std::make_unique<FixedStepIntegrator>(rule, solver.dt_ms);
}
template <class Method>
std::unique_ptr<Integrator> make(const SolverSpec& solver) {
  return std::make_unique<Method>(solver);
}
}  // namespace

const std::vector<IntegratorEntry>& integrators() {
  static const std::vector<IntegratorEntry> entries = {
      {"euler", true, false, make_fixed_step<FixedStepIntegrator::Rule::euler>},
      {"rush_larsen", true, false, make_fixed_step<FixedStepIntegrator::Rule::rush_larsen>},
      {"rush_larsen2", true, true, make_fixed_step<FixedStepIntegrator::Rule::rush_larsen2>},
      {"cvode", false, true, make<CvodeIntegrator>},
      {"adaptive", false, false, make<AdaptiveIntegrator>},
  };
  return entries;
}

bool SolverSpec::fixed_step(const std::string& method) {
  for (const auto& entry : integrators())
    if (method == entry.name) return entry.fixed_step;
  return false;
}

bool reads_population_derivatives(const std::string& method) {
  for (const auto& entry : integrators())
    if (method == entry.name) return entry.reads_population_derivatives;
  return true;
}

std::unique_ptr<Integrator> make_integrator(const SolverSpec& solver) {
  for (const auto& entry : integrators())
    if (solver.method == entry.name) return entry.make(solver);
  throw std::invalid_argument("no integrator named '" + solver.method + "'");
}

}  // namespace fibrodem
