#include "integrate/adaptive.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "integrate/rush_larsen_update.hpp"
#include "model/simd.hpp"

namespace fibrodem {

namespace adaptive_detail {
// One state's row of a block, as the update sees it. History is the type the
// linear forms of the last step are kept in (float or double:
// AdaptiveIntegrator::kFloatHistoryRtol).
template <class History>
struct Row {
  double* y;                  // the population's states (the block's cells)
  double* start;              // saved states at the step's start
  // The linear form at the last accepted step's start (the history), which
  // the step overwrites with its own start's once it has read it.
  History* a_start;
  History* b_start;
  double* first_order;        // the first-order full step, if wanted (null: only its error is)
  const double* a;            // linear form dy/dt = a + b y (the thread's tile)
  const double* b;
  bool exponential;           // gates, and other states with a linear form (stiff_rate)
};
}  // namespace adaptive_detail

namespace {

using simd::Real;
constexpr double kInf = std::numeric_limits<double>::infinity();

using adaptive_detail::Row;

// Loads and stores of the history in lanes, as simd::load and simd::store do
// (a narrower group repeats its last value), in float or double.
Real load_history(const double* p, std::size_t n) { return simd::load(p, n); }
Real load_history(const float* p, std::size_t n) {
  alignas(64) double lanes[simd::kLanes];
  if (n == simd::kLanes)  // (a fixed count: one vector conversion)
    for (std::size_t i = 0; i < simd::kLanes; ++i) lanes[i] = p[i];
  else
    for (std::size_t i = 0; i < simd::kLanes; ++i) lanes[i] = p[i < n ? i : n - 1];
  return Real::load_aligned(lanes);
}
void store_history(double* p, const Real& value, std::size_t n) { simd::store(p, value, n); }
void store_history(float* p, const Real& value, std::size_t n) {
  alignas(64) double lanes[simd::kLanes];
  value.store_aligned(lanes);
  if (n == simd::kLanes)
    for (std::size_t i = 0; i < simd::kLanes; ++i) p[i] = static_cast<float>(lanes[i]);
  else
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<float>(lanes[i]);
}

// Whether any cell of a block gives the state a slope b (a gate, or a stiff
// state of the model's own choosing): its row is then taken exponentially.
template <class T>
bool has_slope(const T* b, std::size_t count) {
  return std::any_of(b, b + count, [](T x) { return x != 0; });
}

double largest_lane(const Real& x) {
  alignas(64) double lanes[simd::kLanes];
  x.store_aligned(lanes);
  return *std::max_element(lanes, lanes + simd::kLanes);
}

// The first-order full step and half step from y0 with the start's linear
// form (A, B): one exp for both (exp(B h) = exp(B h/2)^2). Stage 1 takes the
// half step; stage 2 takes the full step afresh, bit for bit the same, rather
// than keep it a step long in an array per state.
struct FirstOrder {
  Real full, half;
};
FirstOrder first_order_steps(bool exponential, const Real& y0, const Real& A, const Real& B, double h) {
  if (exponential) {
    const Real half = simd::exp(B * (0.5 * h));
    return {rush_larsen_update(y0, A, B, half * half, h), rush_larsen_update(y0, A, B, half, 0.5 * h)};
  }
  const Real slope = A + B * y0;
  return {y0 + h * slope, y0 + (0.5 * h) * slope};
}

// Stage 1 on a row: save the start, write the first-order half step to y.
template <class H>
void first_stage(const Row<H>& row, std::size_t count, double h) {
  for (std::size_t c = 0; c < count; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, count - c);
    const Real y0 = simd::load(row.y + c, n), A = simd::load(row.a + c, n), B = simd::load(row.b + c, n);
    simd::store(row.start + c, y0, n);
    simd::store(row.y + c, first_order_steps(row.exponential, y0, A, B, h).half, n);
  }
}

// Stage 2 on a row: the full step from the start with the midpoint's linear
// form (y holds the midpoint); returns the row's largest error in tolerances
// (inf if a new value left [lo, hi] or is NaN) against the first-order step
// (taken exponentially if first_exponential, as stage 1 took it).
template <class H>
double second_stage(const Row<H>& row, bool first_exponential, std::size_t count, double h, double rtol,
                    double atol_scaled, double lo, double hi) {
  Real worst(0.0);
  Real::batch_bool_type in_limits(true);
  for (std::size_t c = 0; c < count; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, count - c);
    const Real y0 = simd::load(row.start + c, n), A = simd::load(row.a + c, n), B = simd::load(row.b + c, n);
    const Real next = row.exponential ? rush_larsen_update(y0, A, B, simd::exp(B * h), h)
                                      : y0 + h * (A + B * simd::load(row.y + c, n));
    simd::store(row.y + c, next, n);
    const Real first = first_order_steps(first_exponential, y0, load_history(row.a_start + c, n),
                                         load_history(row.b_start + c, n), h)
                           .full;
    if (row.first_order) simd::store(row.first_order + c, first, n);
    const Real tolerance = rtol * simd::fabs(next) + atol_scaled;
    worst = simd::fmax(worst, simd::fabs(next - first) / tolerance);
    in_limits = in_limits & (next >= lo) & (next <= hi);  // NaN fails
  }
  return xsimd::all(in_limits) ? largest_lane(worst) : kInf;
}

// The one-evaluation step on a row: the linear form at the step's middle
// extrapolated from this step's start (a, b) and the previous one's
// (in a_start, b_start; omega = h / (2 h_prev)), the state advanced from its start
// with it (second order). The estimate is its difference to the step with the
// start's own form (first order): for a linear form perturbed by (dA, dB) the
// end moves by h phi1(B h) (dA + dB y_mean) to first order (variation of
// constants; phi1(z) = (e^z - 1)/z, y_mean the mean of the two ends), which
// costs no second exp. Keeps a, b in a_start, b_start for the next step;
// returns the row's largest error in tolerances (inf out of [lo, hi] or NaN).
template <class H>
double extrapolated_row(const Row<H>& row, std::size_t count, double h, double omega, double rtol, double atol_scaled,
                        double lo, double hi) {
  Real worst(0.0);
  Real::batch_bool_type in_limits(true);
  for (std::size_t c = 0; c < count; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, count - c);
    const Real y0 = simd::load(row.y + c, n), A = simd::load(row.a + c, n), B = simd::load(row.b + c, n);
    const Real A_mid = A + omega * (A - load_history(row.a_start + c, n));
    const Real B_mid = B + omega * (B - load_history(row.b_start + c, n));
    store_history(row.a_start + c, A, n);
    store_history(row.b_start + c, B, n);
    simd::store(row.start + c, y0, n);
    Real next, change;  // change: the end's difference to the first-order step
    if (row.exponential) {
      const Real Bh = B_mid * h, E = simd::exp(Bh);
      next = rush_larsen_update(y0, A_mid, B_mid, E, h);
      const auto moving = Bh != 0.0;
      const Real phi1 = simd::select(moving, (E - 1.0) / simd::select(moving, Bh, 1.0), Real(1.0));
      change = h * phi1 * ((A_mid - A) + (B_mid - B) * (0.5 * (y0 + next)));
    } else {
      next = y0 + h * (A_mid + B_mid * y0);
      change = h * ((A_mid - A) + (B_mid - B) * y0);
    }
    simd::store(row.y + c, next, n);
    const Real tolerance = rtol * simd::fabs(next) + atol_scaled;
    worst = simd::fmax(worst, simd::fabs(change) / tolerance);
    in_limits = in_limits & (next >= lo) & (next <= hi);  // NaN fails
  }
  return xsimd::all(in_limits) ? largest_lane(worst) : kInf;
}

// Keeps a block's a, b at the step's start (stage 2 and the next step use them).
template <class H>
void keep_linear_forms(const Row<H>& row, std::size_t count) {
  std::transform(row.a, row.a + count, row.a_start, [](double x) { return static_cast<H>(x); });
  std::transform(row.b, row.b + count, row.b_start, [](double x) { return static_cast<H>(x); });
}

// Largest of `value` and the atomic's (a block's error into the step's).
void atomic_max(std::atomic<double>& target, double value) {
  double seen = target.load(std::memory_order_relaxed);
  while (value > seen && !target.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

// The gap-junction current [pA] into a block's cells at the potentials of
// system.V_mV, in the calling thread's scratch (valid until its next call).
const double* gap_current(const CellSystem& system, const Population& pop, std::size_t offset, std::size_t count) {
  thread_local std::vector<double> current;
  current.resize(kCellsPerBlock);  // no allocation once grown
  system.coupler->current_into(system.V_mV.data(), pop.cells.data() + offset, count, current.data());
  return current.data();
}

}  // namespace

AdaptiveIntegrator::AdaptiveIntegrator(const SolverSpec& solver)
    : rtol_(solver.rtol),
      atol_(solver.atol),
      max_step_ms_(solver.max_step_ms > 0 ? solver.max_step_ms : kInf) {}

// Tolerance scales and buffers (sized once: no allocation per step).
void AdaptiveIntegrator::prepare(CellSystem& system) {
  buffers_.clear();
  system.for_each_population([&](Population& pop) {
    Buffers buf;
    buf.pop = &pop;
    buf.start.resize(pop.y.size());
    const bool coupled = system.coupler && pop.voltage_state >= 0;
    if (coupled)
      buf.F_last.assign(pop.size(), 0.0);
    const auto& states = pop.info().states;
    int rows = 0;
    for (std::size_t k = 0; k < states.size(); ++k) {
      const bool potential = coupled && static_cast<int>(k) == pop.voltage_state;
      buf.form_row.push_back(potential ? -1 : rows++);
    }
    const bool myofilament = std::any_of(system.myofilaments.begin(), system.myofilaments.end(),
                                         [&](const Myofilament& m) { return &m.pop == &pop; });
    const double factor = myofilament ? kMyofilamentToleranceFactor : 1.0;
    buf.rtol = population_rtol(rtol_, myofilament);
    buf.float_history = float_history(buf.rtol);
    const std::size_t forms = static_cast<std::size_t>(rows) * pop.size();
    if (buf.float_history)
      for (auto* v : {&buf.a_last_f, &buf.b_last_f}) v->assign(forms, 0.0f);
    else
      for (auto* v : {&buf.a_last, &buf.b_last}) v->assign(forms, 0.0);
    for (std::size_t k = 0; k < states.size(); ++k) {
      const double magnitude = std::abs(pop.initial_state[k]);
      buf.scale.push_back(factor * (states[k].gate || magnitude == 0 ? 1.0 : magnitude));
    }
    buffers_.push_back(std::move(buf));
  });
  // (The coupling is solved here, not passed to the cells as a current:
  // CellSystem::implicit_coupling, set by the simulation.)
  if (system.coupler && !system.implicit_coupling)
    throw std::logic_error("adaptive: the coupling must not also be an explicit current");
  v_global_.assign(system.cell_count(), 0.0);
  if (system.coupler) system.coupler->restart_implicit();
  solve_tolerance_mV_ = kInf;
  for (const Buffers& buf : buffers_)  // (every coupled population: split over ranks, empty ones too)
    if (system.coupler && buf.pop->voltage_state >= 0)
      solve_tolerance_mV_ = std::min(solve_tolerance_mV_, kSolveToleranceFraction * atol_ *
                                                              buf.scale[static_cast<std::size_t>(buf.pop->voltage_state)]);
  solve_tolerance_mV_ = std::max(solve_tolerance_mV_, kSmallestSolveTolerance_mV);
  history_ = false;
}

AdaptiveIntegrator::Buffers& AdaptiveIntegrator::buffers_of(const Population& pop) {
  for (auto& buf : buffers_)
    if (buf.pop == &pop) return buf;
  throw std::logic_error("adaptive: a population the integrator was not prepared for");
}

// Calls each_row(row, k, buffers, offset) on the rows of a block's states,
// and potential(population, row, offset, count) on a coupled population's
// potential instead. A coupled potential keeps no linear forms (F_last
// instead): its row's a_start, b_start are null, and `potential` reads
// neither.
template <class EachRow, class Potential>
void AdaptiveIntegrator::for_rows(Population& pop, const BlockView& block, bool coupled, EachRow&& each_row,
                                  Potential&& potential) {
  Buffers& buf = buffers_of(pop);
  const std::size_t n = pop.size();
  const std::size_t offset = static_cast<std::size_t>(block.y - pop.y.data());  // the block's first cell
  const auto& states = pop.info().states;
  const auto rows_with_history = [&](auto* a_last, auto* b_last) {
    using History = std::remove_pointer_t<decltype(a_last)>;
    for (std::size_t k = 0; k < states.size(); ++k) {
      const std::size_t at = k * n + offset;
      const int form_row = buf.form_row[k];
      const std::size_t forms_at = static_cast<std::size_t>(form_row) * n + offset;
      const Row<History> row{pop.y.data() + at,
                             buf.start.data() + at,
                             form_row >= 0 ? a_last + forms_at : nullptr,
                             form_row >= 0 ? b_last + forms_at : nullptr,
                             buf.first_order.empty() ? nullptr : buf.first_order.data() + at,
                             block.a + k * block.ab_stride,
                             block.b + k * block.ab_stride,
                             states[k].gate || has_slope(block.b + k * block.ab_stride, block.end)};
      if (coupled && static_cast<int>(k) == pop.voltage_state) potential(pop, row, offset, block.end);
      else each_row(row, k, buf, offset);
    }
  };
  if (buf.float_history) rows_with_history(buf.a_last_f.data(), buf.b_last_f.data());
  else rows_with_history(buf.a_last.data(), buf.b_last.data());
}

double AdaptiveIntegrator::try_step(CellSystem& system, double t, double h) {
  if (system.coupler) {  // V0, for the gap currents at the start (and the other ranks' cells they read, if split)
    system.gather_voltage();
    if (system.refresh_ghost_voltages) system.refresh_ghost_voltages(system.V_mV.data());
  }
  return history_ ? extrapolated_step(system, t, h) : midpoint_step(system, t, h);
}

double AdaptiveIntegrator::midpoint_step(CellSystem& system, double t, double h) {
  // The stimulus at the step's middle: steps never straddle a pulse edge.
  const double t_stim = t + 0.5 * h, theta = 0.5 * h;
  const bool coupled = system.coupler != nullptr;
  // Stage 1: gates and other states to the midpoint (and the first-order full
  // step); for V the right-hand side V0 + theta F0.
  system.evaluate(t_stim, t, [&](Population& pop, const BlockView& block) {
    for_rows(
        pop, block, coupled,
        [&](const auto& row, std::size_t, Buffers&, std::size_t) {
          keep_linear_forms(row, block.end);
          first_stage(row, block.end, h);
        },
        [&](const Population& p, const auto& row, std::size_t offset, std::size_t count) {
          Buffers& buf = buffers_of(p);
          const int* cells = p.cells.data() + offset;
          for (std::size_t c = 0; c < count; ++c) {
            const double V0 = row.y[c], F0 = row.a[c] + row.b[c] * V0;
            row.start[c] = V0;
            buf.F_last[offset + c] = F0;
            v_global_[cells[c]] = V0 + theta * F0;
          }
        });
  });
  if (coupled) {
    solve(system, theta);  // V_half
    for (Buffers& buf : buffers_) {
      Population& pop = *buf.pop;
      if (pop.voltage_state < 0) continue;
      const std::size_t n = pop.size(), row = static_cast<std::size_t>(pop.voltage_state) * n;
      for (std::size_t c = 0; c < n; ++c) {
        const double V_half = v_global_[pop.cells[c]];
        pop.y[row + c] = V_half;  // (until solve_potential, which takes V1's first-order companion from it)
        if (!buf.first_order.empty()) buf.first_order[row + c] = 2 * V_half - buf.start[row + c];
      }
    }
  }
  // Stage 2: the full step from the midpoint's linear forms; for V the
  // right-hand side V0 - theta K V0 + h F_mid (the gap currents at V0, which
  // system.V_mV still holds: an implicit coupling is never gathered in
  // evaluate()).
  std::atomic<double> error{0.0};
  system.evaluate(t_stim, t + theta, [&](Population& pop, const BlockView& block) {
    double block_error = 0;
    for_rows(
        pop, block, coupled,
        [&](const auto& row, std::size_t k, Buffers& buf, std::size_t) {
          // Stage 1's choice, from the start's slopes.
          const bool first_exponential = pop.info().states[k].gate || has_slope(row.b_start, block.end);
          block_error =
              std::max(block_error, second_stage(row, first_exponential, block.end, h, buf.rtol, atol_ * buf.scale[k],
                                                 pop.lower_limit_of(k), pop.upper_limit_of(k)));
        },
        [&](const Population& p, const auto& row, std::size_t offset, std::size_t count) {
          const double* gap = gap_current(system, p, offset, count);
          const int* cells = p.cells.data() + offset;
          for (std::size_t c = 0; c < count; ++c) {
            const double explicit_part = row.start[c] + theta * gap[c] / p.capacitance_pF;
            v_global_[cells[c]] = explicit_part + h * (row.a[c] + row.b[c] * row.y[c]);
          }
        });
    atomic_max(error, block_error);
  });
  return coupled ? solve_potential(system, theta, error.load(), true) : error.load();
}

double AdaptiveIntegrator::extrapolated_step(CellSystem& system, double t, double h) {
  const double t_stim = t + 0.5 * h, theta = 0.5 * h, omega = h / (2 * h_prev_);
  const bool coupled = system.coupler != nullptr;
  std::atomic<double> error{0.0};
  system.evaluate(t_stim, t, [&](Population& pop, const BlockView& block) {
    double block_error = 0;
    for_rows(
        pop, block, coupled,
        [&](const auto& row, std::size_t k, Buffers& buf, std::size_t) {
          block_error = std::max(block_error, extrapolated_row(row, block.end, h, omega, buf.rtol, atol_ * buf.scale[k],
                                                               pop.lower_limit_of(k), pop.upper_limit_of(k)));
        },
        [&](const Population& p, const auto& row, std::size_t offset, std::size_t count) {
          // CNAB2: (I + theta K) V1 = (I - theta K) V0 + h F_mid, F_mid
          // extrapolated; h |F_mid - F0| bounds the difference to the
          // first-order V1 ((I + theta K)^-1 has max norm 1).
          Buffers& buf = buffers_of(p);
          const double atol = atol_ * buf.scale[static_cast<std::size_t>(p.voltage_state)];
          const double* gap = gap_current(system, p, offset, count);
          const int* cells = p.cells.data() + offset;
          for (std::size_t c = 0; c < count; ++c) {
            const double V0 = row.y[c], F0 = row.a[c] + row.b[c] * V0;
            const double F_mid = F0 + omega * (F0 - buf.F_last[offset + c]);
            row.start[c] = V0;
            buf.F_last[offset + c] = F0;
            v_global_[cells[c]] = V0 + theta * gap[c] / p.capacitance_pF + h * F_mid;
            block_error = std::max(block_error, h * std::abs(F_mid - F0) / (rtol_ * std::abs(V0) + atol));
          }
        });
    atomic_max(error, block_error);
  });
  return coupled ? solve_potential(system, theta, error.load(), false) : error.load();
}

void AdaptiveIntegrator::solve(CellSystem& system, double theta) {
  const auto start = std::chrono::steady_clock::now();
  system.coupler->implicit_step(v_global_.data(), theta, solve_tolerance_mV_);
  system.seconds[CellSystem::kCoupling] +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// V1 from (I + theta K) V1 = rhs (in v_global_), into the populations; the
// largest of `error` and V's own (if with_companion, against the first-order
// companion 2 V_half - V0, V_half still in the populations), inf if V left
// its range.
double AdaptiveIntegrator::solve_potential(CellSystem& system, double theta, double error, bool with_companion) {
  solve(system, theta);
  for (Buffers& buf : buffers_) {
    Population& pop = *buf.pop;
    if (pop.voltage_state < 0) continue;
    const std::size_t k = static_cast<std::size_t>(pop.voltage_state), n = pop.size();
    const double lo = pop.lower_limit_of(k), hi = pop.upper_limit_of(k);
    const double atol = atol_ * buf.scale[k];
    for (std::size_t c = 0; c < n; ++c) {
      const double V1 = v_global_[pop.cells[c]];
      if (with_companion) {
        const double companion = 2 * pop.y[k * n + c] - buf.start[k * n + c];
        error = std::max(error, std::abs(V1 - companion) / (rtol_ * std::abs(V1) + atol));
      }
      pop.y[k * n + c] = V1;
      if (!(V1 >= lo && V1 <= hi)) error = kInf;
    }
  }
  return error;
}

// The step was accepted: its start's linear forms, which it left in
// a_last, b_last and F_last, are the history.
void AdaptiveIntegrator::accept(double h) {
  h_prev_ = h;
  history_ = true;
}

void AdaptiveIntegrator::restore() {
  for (auto& buf : buffers_) std::copy(buf.start.begin(), buf.start.end(), buf.pop->y.begin());
}

// The largest step of the grid {1, 1.5} x 2^k x kStepQuantum_ms not above h
// (h itself below the quantum). Consecutive sizes differ by 1.5 or 4/3, and
// any stretch between stops that are multiples of the quantum is tiled by
// grid steps (3 + 1 = 4 quanta, and so on).
double AdaptiveIntegrator::on_grid(double h) {
  if (h <= kStepQuantum_ms) return h;
  const double power = kStepQuantum_ms * std::exp2(std::floor(std::log2(h / kStepQuantum_ms) + 1e-12));
  return 1.5 * power <= h ? 1.5 * power : power;
}

// The step to try after an accepted one. A step cut short of the one wanted
// (by the grid, or to land on a stop) is not the controller's choice. Fed its
// own size and error, the controller would grow it by less than the grid's
// ratio (4/3 or 1.5) whenever the error is above ~0.2 of the tolerance, and
// the grid would floor that back to the step just taken: the step stalls
// (in the wave's upstroke on the Fig. 3 tissue, at 0.023 ms with an error of
// 0.19). And a short step's tiny error would shrink the next step through
// the PI term err_{n-1}^beta2 (after every landing on a sample). So the
// controller is fed the wanted step and the error it would have had,
// err (wanted / step)^(p+1) (p = 1: the estimate goes as h^2); a step cut to
// less than a tenth of the wanted one (a stop just ahead) leaves the wanted
// step and the controller as they were.
double AdaptiveIntegrator::next_after_accepted(double step, double wanted, double err) {
  if (step >= wanted) return controller_.next_step(step, err, true);
  if (step < 0.1 * wanted) return wanted;
  const double ratio = wanted / step;
  return controller_.next_step(wanted, err * ratio * ratio, true);
}

void AdaptiveIntegrator::advance(CellSystem& system, double t_start, double t_end, StepObserver& observer) {
  prepare(system);
  double t = t_start;
  while (observer.next_sample_ms() <= t + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
  double h = std::min(kFirstStep_ms, max_step_ms_);
  controller_.restart();
  while (t < t_end - kTimeEpsilon_ms) {
    // Land on the next stop (a stimulus edge, a sample, or the end).
    const double edge = system.stimulus.next_edge_after(t + kTimeEpsilon_ms);
    double stop = std::min({t_end, edge, observer.next_sample_ms()});
    // Split over ranks: the earliest of every rank's (a rank without traced
    // cells of its own has no sample times), negated for the largest.
    if (system.largest_over_ranks) stop = -system.largest_over_ranks(-stop);
    const double wanted = std::min(h, max_step_ms_);
    const double step = std::min(on_grid(wanted), stop - t);
    const bool lands = step == stop - t;
    double err = try_step(system, t, step);
    if (system.largest_over_ranks) err = system.largest_over_ranks(err);  // every rank accepts or rejects alike
    const bool accepted = err <= 1.0;
    histogram_.add(step, accepted);
    // (An accepted step had every new state in its range: try_step checked them.)
    system.states_checked = system.states_in_limits = accepted;
    if (!accepted) {
      restore();
      // The step left its start's linear forms where the history was (one
      // array per state, not two): the retry is the two-evaluation step,
      // which needs none.
      history_ = false;
      if (step <= kMinStep_ms) fail(system, t, step, err);
      h = std::isfinite(err) ? controller_.next_step(step, err, false) : 0.25 * step;
      h = std::max(h, 0.5 * kMinStep_ms);
      continue;
    }
    accept(step);
    const double t_new = lands ? stop : t + step;
    system.last_step_ms = step;
    h = next_after_accepted(step, wanted, err);
    if (t_new >= edge - kTimeEpsilon_ms) {  // the right-hand side jumps here: no extrapolating over it
      h = std::min(h, kFirstStep_ms);
      controller_.restart();
      history_ = false;
    }
    observer.on_step(t, t_new, nullptr);
    while (observer.next_sample_ms() <= t_new + kTimeEpsilon_ms) observer.on_sample(observer.next_sample_ms());
    t = t_new;
  }
  if (system.coupler) coupling_report_ = system.coupler->describe_solves();
}

std::string AdaptiveIntegrator::report() const {
  return coupling_report_.empty() ? histogram_.describe() : histogram_.describe() + "; " + coupling_report_;
}

// A step at the smallest size still failed: take it once more to name the
// cell and state with the largest error, then stop the run.
void AdaptiveIntegrator::fail(CellSystem& system, double t, double h, double err) {
  history_ = false;  // the two-evaluation step, which leaves a first-order companion for every state here:
  for (Buffers& buf : buffers_) buf.first_order.resize(buf.pop->y.size());
  try_step(system, t, h);
  std::string worst = "?";
  double worst_error = -1;
  const Population* worst_pop = nullptr;
  std::size_t worst_cell = 0;
  for (const Buffers& buf : buffers_) {
    const Population& pop = *buf.pop;
    const std::size_t n = pop.size();
    for (std::size_t k = 0; k < pop.n_states(); ++k)
      for (std::size_t c = 0; c < n; ++c) {
        const double y = pop.y[k * n + c];
        double e = std::abs(y - buf.first_order[k * n + c]) / (buf.rtol * std::abs(y) + atol_ * buf.scale[k]);
        if (!(y >= pop.lower_limit_of(k) && y <= pop.upper_limit_of(k))) e = kInf;
        if (e > worst_error) {
          const StateInfo& state = pop.info().states[k];
          worst_error = e;
          worst_pop = &pop;
          worst_cell = c;
          worst = fmt::format("cell {} ({}, model {}), state '{}' = {:.9g} {}, expected within [{:g}, {:g}]",
                              system.numbering.tissue_cell(static_cast<std::size_t>(pop.cells[c])),
                              cell_type_name(pop.type), pop.info().name, state.name, y, state.unit,
                              state.lower, state.upper);
        }
      }
  }
  restore();
  if (!std::isfinite(err)) {
    // Restored to the step's start: the cell's last finite states.
    std::string states;
    if (worst_pop)
      for (std::size_t k = 0; k < worst_pop->n_states(); ++k)
        states += fmt::format("{}{} = {:.9g}", k ? ", " : "", worst_pop->info().states[k].name,
                              worst_pop->state(static_cast<int>(k), worst_cell));
    throw std::runtime_error(fmt::format(
        "blow-up at t = {:.6g} ms: even a step of {:.3g} ms takes {} out of its range or to NaN, so the solution "
        "itself leaves it: the scene drives the cell there (a stimulus too strong for the cell's capacitance?) or "
        "model {} computes it (check it with: fibrodem check-plugin {}). The cell's states at the step's start (its "
        "last finite values): {}",
        t, h, worst, worst_pop ? worst_pop->info().name : "?", worst_pop ? worst_pop->info().name : "?", states));
  }
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
  s << "; myofilament states at " << kMyofilamentToleranceFactor << " x these";
  if (std::isfinite(max_step_ms_)) s << "; dt <= " << max_step_ms_ << " ms";
  return s.str();
}

}  // namespace fibrodem
