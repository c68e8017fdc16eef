#include "integrate/integrator.hpp"

#include "integrate/adaptive.hpp"
#include "integrate/cvode_integrator.hpp"
#include "integrate/fixed_step.hpp"

namespace fibrodem {

std::unique_ptr<Integrator> make_integrator(const SolverSpec& solver) {
  if (solver.method == "cvode") return std::make_unique<CvodeIntegrator>(solver);
  if (solver.method == "adaptive") return std::make_unique<AdaptiveIntegrator>(solver);
  const auto rule = solver.method == "euler"          ? FixedStepIntegrator::Rule::euler
                    : solver.method == "rush_larsen2" ? FixedStepIntegrator::Rule::rush_larsen2
                                                      : FixedStepIntegrator::Rule::rush_larsen;
  return std::make_unique<FixedStepIntegrator>(rule, solver.dt_ms);
}

}  // namespace fibrodem
