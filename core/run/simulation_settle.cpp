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

// Over the cells of the tissue (split over ranks: each rank's own, then
// over every rank, so that every rank has the same range and stops on the
// same error): V's range at t = 0 and its largest change since V_before_tail.
Simulation::Impl::SettledRange Simulation::Impl::settled_range(const std::vector<double>& V_before_tail) const {
  SettledRange range;
  auto take = [&](std::size_t c) {
    const double V = system.V_mV[c];
    if (!std::isfinite(V)) {
      if (range.unfinite_cell < 0) range.unfinite_cell = system.numbering.tissue_cell(c), range.unfinite_V_mV = V;
      return;
    }
    range.V_min_mV = std::min(range.V_min_mV, V), range.V_max_mV = std::max(range.V_max_mV, V);
    range.tail_change_mV = std::max(range.tail_change_mV, std::abs(V - V_before_tail[c]));
  };
  if (!split.ranks) {
    for (std::size_t c = 0; c < system.V_mV.size(); ++c) {
      take(c);
      if (range.unfinite_cell >= 0) return range;
    }
    return range;
  }
  for (std::size_t c = 0; c < system.numbering.own(); ++c) take(c);
  // Every rank's five numbers (a missing unfinite cell as +inf), combined in rank order.
  const double inf = std::numeric_limits<double>::infinity();
  const double mine[5] = {range.V_min_mV, range.V_max_mV, range.tail_change_mV,
                          range.unfinite_cell < 0 ? inf : static_cast<double>(range.unfinite_cell),
                          range.unfinite_V_mV};
  std::vector<double> every(5 * static_cast<std::size_t>(split.ranks->size()));
  split.ranks->gather_all(mine, 5, every.data());
  SettledRange all;
  double first_unfinite = inf;
  for (std::size_t r = 0; r < static_cast<std::size_t>(split.ranks->size()); ++r) {
    const double* v = &every[5 * r];
    all.V_min_mV = std::min(all.V_min_mV, v[0]), all.V_max_mV = std::max(all.V_max_mV, v[1]);
    all.tail_change_mV = std::max(all.tail_change_mV, v[2]);
    if (v[3] < first_unfinite) first_unfinite = v[3], all.unfinite_V_mV = v[4];
  }
  if (first_unfinite < inf) all.unfinite_cell = static_cast<long long>(first_unfinite);
  return all;
}

void Simulation::Impl::settle_tissue() {
  const double settle_ms = scene.settle.ms;
  if (settle_ms <= 0) return;
  ScopeTimer timer(times.set_up_s);
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

  const SettledRange range = settled_range(V_before_tail);
  if (range.unfinite_cell >= 0)
    throw std::runtime_error(fmt::format("settle: cell {}'s V is {} after {:g} ms of the coupled tissue at rest; "
                                         "the tissue is not stable at rest with these models and parameters",
                                         range.unfinite_cell, range.unfinite_V_mV, settle_ms));
  const double V_min = range.V_min_mV, V_max = range.V_max_mV, tail_change_mV = range.tail_change_mV;
  plan.notes.push_back(fmt::format(
      "settle: the coupled tissue at rest for {:g} ms before t = 0; V from {:.2f} to {:.2f} mV at t = 0, "
      "changing by at most {:.3g} mV over the last {:g} ms",
      settle_ms, V_min, V_max, tail_change_mV, -tail_start_ms));
  log->info("{}", plan.notes.back());
}

}  // namespace fibrodem
