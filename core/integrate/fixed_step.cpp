#include "integrate/fixed_step.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "integrate/rush_larsen_update.hpp"
#include "model/simd.hpp"

namespace fibrodem {

namespace {

// One state's row over cells [begin, end), in SIMD lanes: a gate exactly from
// its linear form (y_inf + (y0 - y_inf) exp(b dt); Euler where b = 0), any
// other state by Euler with the slope taken at ys. False if a new value left
// [lo, hi] or is NaN.
bool update_row(double* y, const double* y0, const double* ys, const double* a, const double* b,
                std::size_t begin, std::size_t end, double dt, bool exponential, double lo, double hi) {
  using simd::Real;
  Real::batch_bool_type in_limits(true);
  for (std::size_t c = begin; c < end; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, end - c);
    const Real A = simd::load(a + c, n), B = simd::load(b + c, n), Y0 = simd::load(y0 + c, n);
    Real next;
    if (exponential) {
      next = rush_larsen_update(Y0, A, B, simd::exp(B * dt), dt);
    } else {
      next = Y0 + dt * (A + B * simd::load(ys + c, n));
    }
    simd::store(y + c, next, n);
    in_limits = in_limits & (next >= lo) & (next <= hi);  // spare lanes repeat a real cell; NaN fails
  }
  return xsimd::all(in_limits);
}


}  // namespace

bool FixedStepIntegrator::update_block(Population& pop, const std::vector<double>& from,
                                       const std::vector<double>& slope_at, std::size_t begin, std::size_t end,
                                       double dt) const {
  const std::size_t n = pop.size();
  const auto& states = pop.info().states;
  const bool exponential_gates = rule_ != Rule::euler;
  bool in_limits = true;
  for (std::size_t k = 0; k < states.size(); ++k)
    in_limits &= update_row(pop.y.data() + k * n, from.data() + k * n, slope_at.data() + k * n,
                            pop.a.data() + k * n, pop.b.data() + k * n, begin, end, dt,
                            exponential_gates && states[k].gate, pop.lower_limit_of(k), pop.upper_limit_of(k));
  return in_limits;
}

bool FixedStepIntegrator::update_view(const Population& pop, const BlockView& block, double dt) const {
  const auto& states = pop.info().states;
  const bool exponential_gates = rule_ != Rule::euler;
  // The view's y is the population's, offset to the block (const only to the model).
  double* y = const_cast<double*>(block.y);
  // Tabulated gates first, from the potentials at the step's start.
  const bool by_table = pop.table_advances_gates;
  if (by_table)
    pop.table->advance_gates(y, block.stride, y + static_cast<std::size_t>(pop.voltage_state) * block.stride, 0,
                             block.end);
  bool in_limits = true;
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (by_table && states[k].voltage_only) continue;
    double* row = y + k * block.stride;
    in_limits &= update_row(row, row, row, block.a + k * block.ab_stride, block.b + k * block.ab_stride, 0,
                            block.end, dt, exponential_gates && states[k].gate, pop.lower_limit_of(k),
                            pop.upper_limit_of(k));
  }
  return in_limits;
}

void FixedStepIntegrator::update_from(Population& pop, const std::vector<double>& from,
                                      const std::vector<double>& slope_at, double dt) const {
  const std::size_t n = pop.size();
  for_each_block(static_cast<long>(pop.block_count()), [&](long block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kCellsPerBlock;
    update_block(pop, from, slope_at, begin, std::min(n, begin + kCellsPerBlock), dt);
  });
}

void FixedStepIntegrator::step(CellSystem& system, double t, double t_next, StepObserver* voltages_to) {
  const double h = t_next - t;
  system.voltages_observed = false;
  if (rule_ != Rule::rush_larsen2) {
    // Each block is updated as soon as it is evaluated (one pass over memory),
    // and its new states checked against their limits on the way.
    std::atomic<bool> out_of_limits{false};
    bool all_checked = true;
    system.for_each_population([&](Population& pop) {
      all_checked &= !pop.lower_limit.empty();
      // (h is t_next - t: the table's step up to round-off, except a short last step)
      pop.table_advances_gates = pop.table && std::abs(pop.table->rush_larsen_step_ms() - h) <= 1e-9 * h;
    });
    // (One pointer captured: std::function keeps it without a heap allocation.)
    // Each block also leaves its cells' new V in next_V_mV (V_mV, which the
    // other blocks read for their gap currents, holds the step's start).
    system.next_V_mV.resize(system.cell_count());
    struct Update {
      const FixedStepIntegrator* integrator;
      double h;
      std::atomic<bool>* out_of_limits;
      double* next_V_mV;
    } update{this, h, &out_of_limits, system.next_V_mV.data()};
    const auto update_block = [u = &update](Population& pop, const BlockView& block) {
      if (!u->integrator->update_view(pop, block, u->h)) u->out_of_limits->store(true, std::memory_order_relaxed);
      if (pop.voltage_state < 0) return;
      const std::size_t offset = static_cast<std::size_t>(block.y - pop.y.data());
      const double* V = block.y + static_cast<std::size_t>(pop.voltage_state) * block.stride;
      const int* cells = pop.cells.data() + offset;
      for (std::size_t c = 0; c < block.end; ++c) u->next_V_mV[cells[c]] = V[c];
    };
    // Then each thread shows its share of the new potentials to the observer
    // (shares cut at whole SIMD widths).
    struct Show {
      StepObserver* observer;
      double t_old, t_new;
      const double* V;
      std::size_t cells;
    } show{voltages_to, t, t_next, system.next_V_mV.data(), system.cell_count()};
    const auto show_voltages = [s = &show](int thread, int threads) {
      const auto edge = [&](int k) {
        if (k == threads) return s->cells;
        return s->cells * static_cast<std::size_t>(k) / static_cast<std::size_t>(threads) / simd::kLanes *
               simd::kLanes;
      };
      s->observer->on_step_voltages(s->t_old, s->t_new, s->V, edge(thread), edge(thread + 1));
    };
    system.evaluate(t, t, update_block, voltages_to ? BlockSchedule::AfterAll(show_voltages) : nullptr);
    std::swap(system.V_mV, system.next_V_mV);
    system.voltage_fresh = true;
    system.voltages_observed = voltages_to != nullptr;
    system.for_each_population([](Population& pop) { pop.table_advances_gates = false; });
    system.states_checked = all_checked;
    system.states_in_limits = !out_of_limits.load();
    return;
  }
  // Second order: half step, midpoint slopes, full step from the start.
  // (Buffers keep their capacity: no allocation after the first step.)
  system.states_checked = false;
  system.evaluate(t, t);
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
  if (rule_ == Rule::rush_larsen) add_rush_larsen_tables(system);
  // The second-order rule's half step reads a and b whole (update_from).
  if (rule_ == Rule::rush_larsen2) system.for_each_population([](Population& pop) { pop.use_derivatives(); });
  // Times are t_start + n*dt (no accumulated round-off); the last step may be short.
  const auto steps = static_cast<long long>(std::ceil((t_end - t_start) / dt_ms_ - 1e-9));
  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  const int every = std::max(1, system.coupling_every);
  double since_coupling = 0;  // time the implicit coupling still owes
  if (system.coupler) system.coupler->restart_implicit();
  for (long long n = 0; n < steps; ++n) {
    const double t_next = (n + 1 == steps) ? t_end : t_start + static_cast<double>(n + 1) * dt_ms_;
    const double h = t_next - t;
    system.refresh_coupling = n % every == 0;
    const bool split_coupling =
        system.coupler && system.implicit_coupling && ((n + 1) % every == 0 || n + 1 == steps);
    step(system, t, t_next, split_coupling ? nullptr : &observer);
    since_coupling += h;
    if (split_coupling) {
      const auto start = std::chrono::steady_clock::now();
      system.gather_voltage();
      system.coupler->implicit_step(system.V_mV.data(), since_coupling, kCouplingSolveTolerance_mV);
      since_coupling = 0;
      system.scatter_voltage();
      system.seconds[CellSystem::kCoupling] +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    system.last_step_ms = h;
    observer.on_step(t, t_next, nullptr);
    while (observer.next_sample_ms() <= t_next + kTimeEpsilon_ms)
      observer.on_sample(observer.next_sample_ms());
    t = t_next;
  }
}

// Lookup tables (solver.lookup_tables) gain the Rush-Larsen columns of this
// step: the tabulated gates then cost no exp() at all.
void FixedStepIntegrator::add_rush_larsen_tables(CellSystem& system) const {
  system.for_each_population([&](Population& pop) {
    if (!pop.table || pop.table->rush_larsen_step_ms() == dt_ms_) return;
    if (auto with_step = pop.table->with_rush_larsen_step(dt_ms_)) pop.table = with_step;
  });
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
