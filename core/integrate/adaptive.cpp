#include "integrate/adaptive.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "model/simd.hpp"

namespace fibrodem {

namespace {

using simd::Real;
constexpr double kInf = std::numeric_limits<double>::infinity();

// One state's row of a block, as the update sees it.
struct Row {
  double* y;                  // the population's states (the block's cells)
  double* start;              // saved states at the step's start
  double* first_order;        // first-order full step (the error estimate)
  const double* a;            // linear form dy/dt = a + b y (the thread's tile)
  const double* b;
  bool exponential;           // gates, and other states with a linear form (stiff_rate)
};

// Whether any cell of a block gives the state a slope b (a gate, or a stiff
// state of the model's own choosing): its row is then taken exponentially.
bool has_slope(const double* b, std::size_t count) {
  return std::any_of(b, b + count, [](double x) { return x != 0.0; });
}

// y_inf + (y0 - y_inf) * E, E = exp(B dt); where B = 0, Euler from y0.
Real exponential_update(const Real& y0, const Real& A, const Real& B, const Real& E, double dt) {
  const auto moving = B != 0.0;
  const Real y_inf = -A / simd::select(moving, B, 1.0);
  return simd::select(moving, y_inf + (y0 - y_inf) * E, y0 + dt * A);
}

// Stage 1 on a row: save the start, write the first-order full step to
// first_order and the first-order half step to y.
void first_stage(const Row& row, std::size_t count, double h) {
  for (std::size_t c = 0; c < count; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, count - c);
    const Real y0 = simd::load(row.y + c, n), A = simd::load(row.a + c, n), B = simd::load(row.b + c, n);
    simd::store(row.start + c, y0, n);
    if (row.exponential) {
      const Real half = simd::exp(B * (0.5 * h));  // exp(B h) = half^2: one exp
      simd::store(row.first_order + c, exponential_update(y0, A, B, half * half, h), n);
      simd::store(row.y + c, exponential_update(y0, A, B, half, 0.5 * h), n);
    } else {
      const Real slope = A + B * y0;
      simd::store(row.first_order + c, y0 + h * slope, n);
      simd::store(row.y + c, y0 + (0.5 * h) * slope, n);
    }
  }
}

// Stage 2 on a row: the full step from the start with the midpoint's linear
// form (y holds the midpoint); returns the row's largest error in tolerances
// (inf if a new value left [lo, hi] or is NaN).
double second_stage(const Row& row, std::size_t count, double h, double rtol, double atol_scaled, double lo,
                    double hi) {
  Real worst(0.0);
  Real::batch_bool_type in_limits(true);
  for (std::size_t c = 0; c < count; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, count - c);
    const Real y0 = simd::load(row.start + c, n), A = simd::load(row.a + c, n), B = simd::load(row.b + c, n);
    const Real next = row.exponential ? exponential_update(y0, A, B, simd::exp(B * h), h)
                                      : y0 + h * (A + B * simd::load(row.y + c, n));
    simd::store(row.y + c, next, n);
    const Real tolerance = rtol * simd::fabs(next) + atol_scaled;
    worst = simd::fmax(worst, simd::fabs(next - simd::load(row.first_order + c, n)) / tolerance);
    in_limits = in_limits & (next >= lo) & (next <= hi);  // NaN fails
  }
  if (!xsimd::all(in_limits)) return kInf;
  alignas(64) double lanes[simd::kLanes];
  worst.store_aligned(lanes);
  return *std::max_element(lanes, lanes + simd::kLanes);
}

// Largest of `value` and the atomic's (a block's error into the step's).
void atomic_max(std::atomic<double>& target, double value) {
  double seen = target.load(std::memory_order_relaxed);
  while (value > seen && !target.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

double limit(const std::vector<double>& limits, std::size_t k, double fallback) {
  return limits.empty() ? fallback : limits[k];
}

}  // namespace

AdaptiveIntegrator::AdaptiveIntegrator(const SolverSpec& solver)
    : rtol_(solver.rtol), atol_(solver.atol), max_step_ms_(solver.max_step_ms > 0 ? solver.max_step_ms : kInf) {}

// Tolerance scales and buffers (sized once: no allocation per step).
void AdaptiveIntegrator::prepare(CellSystem& system) {
  buffers_.clear();
  system.for_each_population([&](Population& pop) {
    Buffers buf;
    buf.pop = &pop;
    buf.start.resize(pop.y.size());
    buf.first_order.resize(pop.y.size());
    const auto& states = pop.info().states;
    for (std::size_t k = 0; k < states.size(); ++k) {
      const double magnitude = std::abs(pop.initial_state[k]);
      buf.scale.push_back(states[k].gate || magnitude == 0 ? 1.0 : magnitude);
    }
    buffers_.push_back(std::move(buf));
  });
  // (The coupling is solved here, not passed to the cells as a current:
  // CellSystem::implicit_coupling, set by the simulation.)
  if (system.coupler && !system.implicit_coupling)
    throw std::logic_error("adaptive: the coupling must not also be an explicit current");
  v_half_.assign(system.cell_count(), 0.0);
  v_full_.assign(system.cell_count(), 0.0);
  gap_pA_.assign(system.cell_count(), 0.0);
}

AdaptiveIntegrator::Buffers& AdaptiveIntegrator::buffers_of(const Population& pop) {
  for (auto& buf : buffers_)
    if (buf.pop == &pop) return buf;
  throw std::logic_error("adaptive: a population the integrator was not prepared for");
}

double AdaptiveIntegrator::try_step(CellSystem& system, double t, double h) {
  // The stimulus at the step's middle: steps never straddle a pulse edge.
  const double t_stim = t + 0.5 * h, theta = 0.5 * h;
  const bool coupled = system.coupler != nullptr;
  if (coupled) system.gather_voltage();  // V0, for the gap currents at the start
  // Calls each_row(row, k, buffers) on the rows of a block's states, and
  // potential(offset) on a coupled population's potential instead.
  auto rows_of = [&](Population& pop, const BlockView& block, auto&& each_row, auto&& potential) {
    Buffers& buf = buffers_of(pop);
    const std::size_t n = pop.size();
    const std::size_t offset = static_cast<std::size_t>(block.y - pop.y.data());  // the block's first cell
    const auto& states = pop.info().states;
    for (std::size_t k = 0; k < states.size(); ++k) {
      const Row row{pop.y.data() + k * n + offset, buf.start.data() + k * n + offset,
                    buf.first_order.data() + k * n + offset, block.a + k * block.ab_stride,
                    block.b + k * block.ab_stride,
                    states[k].gate || has_slope(block.b + k * block.ab_stride, block.end)};
      if (coupled && static_cast<int>(k) == pop.voltage_state) potential(pop, row, offset, block.end);
      else each_row(row, k, buf);
    }
  };
  // Stage 1: gates and other states to the midpoint (and the first-order full
  // step); for V the right-hand sides V0 + theta F0 and V0 - theta K V0.
  system.evaluate(t_stim, t, [&](Population& pop, const BlockView& block) {
    rows_of(
        pop, block, [&](const Row& row, std::size_t, Buffers&) { first_stage(row, block.end, h); },
        [&](const Population& p, const Row& row, std::size_t offset, std::size_t count) {
          const int* cells = p.cells.data() + offset;
          system.coupler->current_into(system.V_mV.data(), cells, count, gap_pA_.data());
          for (std::size_t c = 0; c < count; ++c) {
            const double V0 = row.y[c];
            row.start[c] = V0;
            v_half_[cells[c]] = V0 + theta * (row.a[c] + row.b[c] * V0);
            v_full_[cells[c]] = V0 + theta * gap_pA_[cells[c]] / p.capacitance_pF;
          }
        });
  });
  if (coupled) {
    system.coupler->implicit_step(v_half_.data(), theta);  // V_half
    for (Buffers& buf : buffers_) {
      const Population& pop = *buf.pop;
      if (pop.voltage_state < 0) continue;
      const std::size_t n = pop.size(), row = static_cast<std::size_t>(pop.voltage_state) * n;
      for (std::size_t c = 0; c < n; ++c) {
        const double V_half = v_half_[pop.cells[c]];
        const_cast<Population&>(pop).y[row + c] = V_half;
        buf.first_order[row + c] = 2 * V_half - buf.start[row + c];
      }
    }
  }
  // Stage 2: the full step from the midpoint's linear forms.
  std::atomic<double> error{0.0};
  system.evaluate(t_stim, t + theta, [&](Population& pop, const BlockView& block) {
    double block_error = 0;
    rows_of(
        pop, block,
        [&](const Row& row, std::size_t k, Buffers& buf) {
          block_error = std::max(block_error, second_stage(row, block.end, h, rtol_, atol_ * buf.scale[k],
                                                           limit(pop.lower_limit, k, -kInf),
                                                           limit(pop.upper_limit, k, kInf)));
        },
        [&](const Population& p, const Row& row, std::size_t offset, std::size_t count) {
          const int* cells = p.cells.data() + offset;
          for (std::size_t c = 0; c < count; ++c) v_full_[cells[c]] += h * (row.a[c] + row.b[c] * row.y[c]);
        });
    atomic_max(error, block_error);
  });
  if (!coupled) return error.load();
  system.coupler->implicit_step(v_full_.data(), theta);  // V1
  double worst = error.load();
  for (Buffers& buf : buffers_) {
    Population& pop = const_cast<Population&>(*buf.pop);
    if (pop.voltage_state < 0) continue;
    const std::size_t k = static_cast<std::size_t>(pop.voltage_state), n = pop.size();
    const double lo = limit(pop.lower_limit, k, -kInf), hi = limit(pop.upper_limit, k, kInf);
    const double atol = atol_ * buf.scale[k];
    for (std::size_t c = 0; c < n; ++c) {
      const double V1 = v_full_[pop.cells[c]];
      pop.y[k * n + c] = V1;
      if (!(V1 >= lo && V1 <= hi)) worst = kInf;
      worst = std::max(worst, std::abs(V1 - buf.first_order[k * n + c]) / (rtol_ * std::abs(V1) + atol));
    }
  }
  return worst;
}

void AdaptiveIntegrator::restore() {
  for (auto& buf : buffers_) std::copy(buf.start.begin(), buf.start.end(), const_cast<Population*>(buf.pop)->y.begin());
}

// The largest step 2^k kStepQuantum_ms not above h (at least the quantum).
double AdaptiveIntegrator::on_grid(double h) {
  if (h <= kStepQuantum_ms) return h;
  return kStepQuantum_ms * std::exp2(std::floor(std::log2(h / kStepQuantum_ms) + 1e-12));
}

void AdaptiveIntegrator::advance(CellSystem& system, double t_start, double t_end, StepObserver& observer) {
  prepare(system);
  system.states_checked = false;
  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  double h = std::min(kFirstStep_ms, max_step_ms_);
  controller_.restart();
  while (t < t_end - kTimeEpsilon_ms) {
    // Land on the next stop (a stimulus edge, a sample, or the end).
    const double edge = system.stimulus.next_edge_after(t + kTimeEpsilon_ms);
    const double stop = std::min({t_end, edge, observer.next_sample_ms()});
    const double wanted = std::min(h, max_step_ms_);
    const double step = std::min(on_grid(wanted), stop - t);
    const bool lands = step == stop - t;
    const double err = try_step(system, t, step);
    const bool accepted = err <= 1.0;
    histogram_.add(step, accepted);
    if (!accepted) {
      restore();
      if (step <= kMinStep_ms) fail(system, t, step, err);
      h = std::isfinite(err) ? controller_.next_step(step, err, false) : 0.25 * step;
      h = std::max(h, 0.5 * kMinStep_ms);
      continue;
    }
    const double t_new = lands ? stop : t + step;
    system.last_step_ms = step;
    // The next step grows from the one wanted, not from a shorter one taken
    // to land on a stop or on the grid.
    h = std::max(controller_.next_step(step, err, true), step < wanted ? wanted : 0.0);
    if (t_new >= edge - kTimeEpsilon_ms) {  // the right-hand side jumps here
      h = std::min(h, kFirstStep_ms);
      controller_.restart();
    }
    observer.on_step(t, t_new, nullptr);
    while (observer.next_sample_ms() <= t_new + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
    t = t_new;
  }
}

// A step at the smallest size still failed: take it once more to name the
// cell and state with the largest error, then stop the run.
void AdaptiveIntegrator::fail(CellSystem& system, double t, double h, double err) {
  try_step(system, t, h);
  std::string worst = "?";
  double worst_error = -1;
  for (const Buffers& buf : buffers_) {
    const Population& pop = *buf.pop;
    const std::size_t n = pop.size();
    for (std::size_t k = 0; k < pop.n_states(); ++k)
      for (std::size_t c = 0; c < n; ++c) {
        const double y = pop.y[k * n + c];
        double e = std::abs(y - buf.first_order[k * n + c]) / (rtol_ * std::abs(y) + atol_ * buf.scale[k]);
        if (!(y >= limit(pop.lower_limit, k, -kInf) && y <= limit(pop.upper_limit, k, kInf))) e = kInf;
        if (e > worst_error) {
          const StateInfo& state = pop.info().states[k];
          worst_error = e;
          worst = fmt::format("cell {} ({}, model {}), state '{}' = {:.9g} {}, expected within [{:g}, {:g}]",
                              pop.cells[c], cell_type_name(pop.type), pop.info().name, state.name, y, state.unit,
                              state.lower, state.upper);
        }
      }
  }
  restore();
  if (!std::isfinite(err))
    throw std::runtime_error(fmt::format(
        "blow-up at t = {:.6g} ms: even a step of {:.3g} ms takes {} out of its range or to NaN, so the solution "
        "itself leaves it: the scene drives the cell there (a stimulus too strong for the cell's capacitance?)",
        t, h, worst));
  throw std::runtime_error(fmt::format(
      "adaptive step control failed at t = {:.6g} ms: a step of {:.3g} ms still has a local error {:.3g} times the "
      "tolerance (rtol {:g}, atol {:g}; worst: {}); loosen solver.rtol and solver.atol, or use solver.method "
      "\"cvode\"",
      t, h, err, rtol_, atol_, worst));
}

std::string AdaptiveIntegrator::describe() const {
  std::ostringstream s;
  s << "adaptive second-order Rush-Larsen (embedded first-order estimate, PI step control), rtol " << rtol_
    << ", atol " << atol_ << " x each state's scale; gap junctions implicit (Crank-Nicolson)";
  if (std::isfinite(max_step_ms_)) s << "; dt <= " << max_step_ms_ << " ms";
  return s.str();
}

}  // namespace fibrodem
