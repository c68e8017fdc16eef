#include "integrate/fixed_step.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace fibrodem {

void FixedStepIntegrator::update_from(Population& pop, const std::vector<double>& from,
                                      const std::vector<double>& slope_at, double dt) const {
  const std::size_t n = pop.size();
  const auto& states = pop.info().states;
  const bool exponential_gates = rule_ != Rule::euler;
  const auto blocks = static_cast<long>((n + kCellsPerBlock - 1) / kCellsPerBlock);
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (long block = 0; block < blocks; ++block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kCellsPerBlock;
    const std::size_t end = std::min(n, begin + kCellsPerBlock);
    for (std::size_t k = 0; k < states.size(); ++k) {
      double* y = pop.y.data() + k * n;
      const double* y0 = from.data() + k * n;
      const double* ys = slope_at.data() + k * n;
      const double* a = pop.a.data() + k * n;
      const double* b = pop.b.data() + k * n;
      if (exponential_gates && states[k].gate) {
        for (std::size_t c = begin; c < end; ++c) {
          if (b[c] != 0.0) {
            const double y_inf = -a[c] / b[c];
            y[c] = y_inf + (y0[c] - y_inf) * std::exp(b[c] * dt);
          } else {
            y[c] = y0[c] + dt * a[c];
          }
        }
      } else {
        for (std::size_t c = begin; c < end; ++c) y[c] = y0[c] + dt * (a[c] + b[c] * ys[c]);
      }
    }
  }
}

void FixedStepIntegrator::step(CellSystem& system, double t, double h) {
  system.evaluate(t, t);
  if (rule_ != Rule::rush_larsen2) {
    system.for_each_population([&](Population& pop) { update_states(pop, h); });
    return;
  }
  // Second order: half step, midpoint slopes, full step from the start.
  // (Buffers keep their capacity: no allocation after the first step.)
  std::size_t p = 0;
  start_.resize(system.populations.size() + system.myofilaments.size());
  midpoint_.resize(start_.size());
  system.for_each_population([&](Population& pop) {
    start_[p++] = pop.y;
    update_states(pop, 0.5 * h);
  });
  system.evaluate(t + 0.5 * h, t + 0.5 * h);
  p = 0;
  system.for_each_population([&](Population& pop) {
    midpoint_[p] = pop.y;
    update_from(pop, start_[p], midpoint_[p], h);
    ++p;
  });
}

void FixedStepIntegrator::advance(CellSystem& system, double t_start, double t_end,
                                  StepObserver& observer) {
  // Times are t_start + n*dt (no accumulated round-off); the last step may be short.
  const auto steps = static_cast<long long>(std::ceil((t_end - t_start) / dt_ms_ - 1e-9));
  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  const int every = std::max(1, system.coupling_every);
  double since_coupling = 0;  // time the implicit coupling still owes
  for (long long n = 0; n < steps; ++n) {
    const double t_next = (n + 1 == steps) ? t_end : t_start + static_cast<double>(n + 1) * dt_ms_;
    const double h = t_next - t;
    system.refresh_coupling = n % every == 0;
    step(system, t, h);
    since_coupling += h;
    if (system.coupler && system.implicit_coupling && ((n + 1) % every == 0 || n + 1 == steps)) {
      const auto start = std::chrono::steady_clock::now();
      system.gather_voltage();
      system.coupler->implicit_step(system.V_mV.data(), since_coupling);
      since_coupling = 0;
      system.scatter_voltage();
      system.seconds[CellSystem::kCoupling] +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    observer.on_step(t, t_next, nullptr);
    while (observer.next_sample_ms() <= t_next + kTimeEpsilon_ms)
      observer.on_sample(observer.next_sample_ms());
    t = t_next;
  }
}

std::string FixedStepIntegrator::describe() const {
  std::ostringstream s;
  switch (rule_) {
    case Rule::euler: s << "forward Euler"; break;
    case Rule::rush_larsen: s << "Rush-Larsen (gates exact, other states Euler)"; break;
    case Rule::rush_larsen2: s << "second-order Rush-Larsen (exponential midpoint)"; break;
  }
  s << ", dt = " << dt_ms_ << " ms";
  return s.str();
}

}  // namespace fibrodem
