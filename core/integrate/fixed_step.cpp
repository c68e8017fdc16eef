#include "integrate/fixed_step.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fibrodem {

void FixedStepIntegrator::update_states(Population& pop, double dt) const {
  const std::size_t n = pop.size();
  const auto& states = pop.info().states;
  const auto blocks = static_cast<long>((n + kCellsPerBlock - 1) / kCellsPerBlock);
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (long block = 0; block < blocks; ++block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kCellsPerBlock;
    const std::size_t end = std::min(n, begin + kCellsPerBlock);
    for (std::size_t k = 0; k < states.size(); ++k) {
      double* y = pop.y.data() + k * n;
      const double* a = pop.a.data() + k * n;
      const double* b = pop.b.data() + k * n;
      if (rule_ == Rule::rush_larsen && states[k].gate) {
        for (std::size_t c = begin; c < end; ++c) {
          if (b[c] != 0.0) {
            const double y_inf = -a[c] / b[c];
            y[c] = y_inf + (y[c] - y_inf) * std::exp(b[c] * dt);
          } else {
            y[c] += dt * a[c];
          }
        }
      } else {
        for (std::size_t c = begin; c < end; ++c) y[c] += dt * (a[c] + b[c] * y[c]);
      }
    }
  }
}

void FixedStepIntegrator::advance(CellSystem& system, double t_start, double t_end,
                                  StepObserver& observer) {
  // Times are t_start + n*dt (no accumulated round-off); the last step may be short.
  const auto steps = static_cast<long long>(std::ceil((t_end - t_start) / dt_ms_ - 1e-9));
  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  for (long long n = 0; n < steps; ++n) {
    const double t_next = (n + 1 == steps) ? t_end : t_start + static_cast<double>(n + 1) * dt_ms_;
    const double h = t_next - t;
    system.evaluate(t, t);
    system.for_each_population([&](Population& pop) { update_states(pop, h); });
    if (system.coupler && system.implicit_coupling) {
      system.gather_voltage();
      system.coupler->implicit_step(system.V_mV.data(), h);
      system.scatter_voltage();
    }
    observer.on_step(t, t_next, nullptr);
    while (observer.next_sample_ms() <= t_next + kTimeEpsilon_ms)
      observer.on_sample(observer.next_sample_ms());
    t = t_next;
  }
}

std::string FixedStepIntegrator::describe() const {
  std::ostringstream s;
  s << (rule_ == Rule::euler ? "forward Euler" : "Rush-Larsen (gates exact, other states Euler)")
    << ", dt = " << dt_ms_ << " ms";
  return s.str();
}

}  // namespace fibrodem
