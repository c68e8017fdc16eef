// settle: before t = 0 the coupled tissue runs at rest, so that each cell
// starts where the coupling holds it. Each type's own settle (settle.cpp) runs
// one uncoupled cell; a fibroblast coupled to myocytes rests 15-20 mV below
// its isolated rest (seed paper Fig. 3: -47 mV alone, about -65 mV coupled),
// and without this every trace would open with that transient.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "run/simulation_impl.hpp"

namespace fibrodem {

namespace {

// The settle wants no sample and does nothing per step: no measurement, no
// output, no mechanics.
class Unobserved final : public StepObserver {
 public:
  double next_sample_ms() const override { return std::numeric_limits<double>::infinity(); }
  void on_sample(double) override {}
  void on_step(double, double, const double*) override {}
};

}  // namespace

void Simulation::Impl::settle_tissue() {
  const double settle_ms = scene.settle.ms;
  if (settle_ms <= 0) return;
  ScopeTimer timer(set_up_seconds);
  Stimulus stimulus = std::move(system.stimulus);
  system.stimulus = Stimulus();
  Unobserved unobserved;
  // The last tenth apart, to say how far V still moved at its end.
  const double tail_start_ms = -0.1 * settle_ms;
  integrator->advance(system, -settle_ms, tail_start_ms, unobserved);
  system.gather_voltage();
  const std::vector<double> V_before_tail = system.V_mV;
  integrator->advance(system, tail_start_ms, 0.0, unobserved);
  system.gather_voltage();
  system.stimulus = std::move(stimulus);
  // A fresh integrator: no step history from the settle carries into t = 0.
  integrator = make_integrator(scene.solver);

  double tail_change_mV = 0, V_min = std::numeric_limits<double>::infinity(), V_max = -V_min;
  for (std::size_t c = 0; c < system.V_mV.size(); ++c) {
    const double V = system.V_mV[c];
    if (!std::isfinite(V))
      throw std::runtime_error(fmt::format("settle: cell {}'s V is {} after {:g} ms of the coupled tissue at rest; "
                                           "the tissue is not stable at rest with these models and parameters",
                                           c, V, settle_ms));
    V_min = std::min(V_min, V), V_max = std::max(V_max, V);
    tail_change_mV = std::max(tail_change_mV, std::abs(V - V_before_tail[c]));
  }
  plan.notes.push_back(fmt::format(
      "settle: the coupled tissue at rest for {:g} ms before t = 0; V from {:.2f} to {:.2f} mV at t = 0, "
      "changing by at most {:.3g} mV over the last {:g} ms",
      settle_ms, V_min, V_max, tail_change_mV, -tail_start_ms));
  log->info("{}", plan.notes.back());
}

}  // namespace fibrodem
