#include "integrate/stability.hpp"

#include <cmath>
#include <sstream>

namespace fibrodem {

namespace {
// Probe from 10 mV below the model's initial (resting) potential to +60 mV: a
// gate's rate far below rest (tau_m at -100 mV) would never be met.
constexpr double kBelowRest_mV = 10.0, kProbeHigh_mV = 60.0, kProbeStep_mV = 0.5;

// The fastest gate rate |b| of a population's model over the probe voltages.
void probe_gates(const Population& pop, StabilityEstimate& estimate) {
  if (pop.voltage_state < 0) return;
  Population probe;
  probe.model = pop.model;
  probe.params = pop.params;
  probe.initial_state = pop.initial_state;
  probe.voltage_state = pop.voltage_state;
  const double low = pop.initial_state[pop.voltage_state] - kBelowRest_mV;
  if (!(low < kProbeHigh_mV)) return;
  const auto n = static_cast<std::size_t>((kProbeHigh_mV - low) / kProbeStep_mV) + 1;
  probe.cells.resize(n);
  probe.reset();
  for (std::size_t c = 0; c < n; ++c) probe.state(pop.voltage_state, c) = low + kProbeStep_mV * c;
  probe.evaluate(0.0);
  const auto& states = pop.info().states;
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (!states[k].gate) continue;
    for (std::size_t c = 0; c < n; ++c) {
      const double rate = std::abs(probe.b[k * n + c]);
      if (rate > 0 && 2.0 / rate < estimate.gate_limit_ms) {
        estimate.gate_limit_ms = 2.0 / rate;
        std::ostringstream where;
        where << pop.info().name << ": gate " << states[k].name << " at V = " << low + kProbeStep_mV * c
              << " mV";
        estimate.fastest_gate = where.str();
      }
    }
  }
}
}  // namespace

StabilityEstimate estimate_explicit_stability(CellSystem& system, bool euler_gates, bool explicit_coupling) {
  StabilityEstimate estimate;
  if (explicit_coupling && system.coupler) {
    const double rate = system.coupler->max_rate_per_ms();
    if (rate > 0) estimate.coupling_limit_ms = 2.0 / rate;
  }
  if (euler_gates)
    system.for_each_population([&](const Population& pop) { probe_gates(pop, estimate); });
  return estimate;
}

}  // namespace fibrodem
