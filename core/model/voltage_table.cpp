#include "model/voltage_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "model/population.hpp"
#include "model/simd.hpp"

namespace fibrodem {

std::shared_ptr<VoltageTable> VoltageTable::build(const Population& pop, double v_min_mV, double v_max_mV,
                                                  double step_mV) {
  if (pop.voltage_state < 0 || !(v_max_mV > v_min_mV) || !(step_mV > 0)) return nullptr;
  auto table = std::make_shared<VoltageTable>();
  const auto& states = pop.info().states;
  for (std::size_t k = 0; k < states.size(); ++k)
    if (states[k].voltage_only) table->gates_.push_back(static_cast<int>(k));
  if (table->gates_.empty()) return nullptr;
  table->v_min_ = v_min_mV;
  table->step_ = step_mV;
  table->inv_step_ = 1.0 / step_mV;
  table->points_ = static_cast<std::size_t>(std::llround((v_max_mV - v_min_mV) / step_mV)) + 1;

  // The probe: one cell per table point, exact model (no table on the probe).
  Population probe;
  probe.type = pop.type;
  probe.model = pop.model;
  probe.params = pop.params;
  probe.initial_state = pop.initial_state;
  probe.voltage_state = pop.voltage_state;
  probe.scalar_reference = pop.scalar_reference;
  const std::size_t n = table->points_;
  probe.cells.resize(n);
  probe.reset();
  for (std::size_t c = 0; c < n; ++c)
    probe.state(pop.voltage_state, c) = v_min_mV + step_mV * static_cast<double>(c);
  probe.evaluate(0.0);

  const std::size_t g = table->gates_.size();
  table->rows_.resize(n * 2 * g);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t i = 0; i < g; ++i) {
      const std::size_t k = static_cast<std::size_t>(table->gates_[i]);
      table->rows_[c * 2 * g + 2 * i] = probe.a[k * n + c];
      table->rows_[c * 2 * g + 2 * i + 1] = probe.b[k * n + c];
    }
  return table;
}

void VoltageTable::fill(const BlockView& block, int voltage_state) const {
  const std::size_t g = gates_.size(), width = 2 * g;
  const double* V = block.y + static_cast<std::size_t>(voltage_state) * block.stride;
  const std::size_t ab_stride = block.ab_stride ? block.ab_stride : block.stride;
  long long clamped = 0;
  for (std::size_t c = block.begin; c < block.end; ++c) {
    const auto [i, w] = position(V[c], clamped);
    const double* r0 = rows_.data() + i * width;
    const double* r1 = r0 + width;
    for (std::size_t q = 0; q < g; ++q) {
      const std::size_t at = static_cast<std::size_t>(gates_[q]) * ab_stride + c;
      block.a[at] = r0[2 * q] + w * (r1[2 * q] - r0[2 * q]);
      block.b[at] = r0[2 * q + 1] + w * (r1[2 * q + 1] - r0[2 * q + 1]);
    }
  }
  if (clamped != 0) clamps_.fetch_add(clamped, std::memory_order_relaxed);
}

std::shared_ptr<VoltageTable> VoltageTable::with_rush_larsen_step(double dt_ms) const {
  for (std::size_t r = 1; r < rows_.size(); r += 2)
    if (rows_[r] == 0.0) return nullptr;  // a gate standing still there has no y_inf
  auto t = std::make_shared<VoltageTable>();
  t->v_min_ = v_min_;
  t->step_ = step_;
  t->inv_step_ = inv_step_;
  t->points_ = points_;
  t->gates_ = gates_;
  t->rows_ = rows_;
  t->rl_dt_ = dt_ms;
  t->rl_rows_.resize(rows_.size());
  for (std::size_t r = 0; r < rows_.size(); r += 2) {
    const double a = rows_[r], b = rows_[r + 1];
    t->rl_rows_[r] = -a / b;
    t->rl_rows_[r + 1] = std::exp(b * dt_ms);
  }
  return t;
}

void VoltageTable::advance_gates(double* y, std::size_t stride, const double* V, std::size_t begin,
                                 std::size_t end) const {
  // In lanes of cells: each lane's table rows are gathered (every cell has its
  // own V), the rest is arithmetic on whole registers.
  using simd::Real;
  using Index = xsimd::batch<std::int64_t>;
  static_assert(Index::size == Real::size);
  const std::size_t g = gates_.size(), width = 2 * g;
  const double last = static_cast<double>(points_ - 1);
  long long clamped = 0;
  for (std::size_t c = begin; c < end; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, end - c);
    // Table position, as position() does it: below the table or NaN -> row 0,
    // above -> the last row; both counted.
    Real x = (simd::load(V + c, n) - v_min_) * inv_step_;
    const auto below = !(x >= 0.0), above = x > last;
    alignas(64) bool out[simd::kLanes];
    (below | above).store_aligned(out);
    for (std::size_t i = 0; i < n; ++i) clamped += out[i];
    x = simd::select(below, 0.0, simd::select(above, last, x));
    const Index row = xsimd::min(xsimd::to_int(simd::floor(x)), Index(static_cast<std::int64_t>(points_) - 2));
    const Real w = x - xsimd::to_float(row);
    const Index at = row * static_cast<std::int64_t>(width);
    for (std::size_t q = 0; q < g; ++q) {
      const double* column = rl_rows_.data() + 2 * q;
      const Real y0 = Real::gather(column, at), y1 = Real::gather(column + width, at);
      const Real e0 = Real::gather(column + 1, at), e1 = Real::gather(column + 1 + width, at);
      const Real y_inf = y0 + w * (y1 - y0), E = e0 + w * (e1 - e0);
      double* gate = y + static_cast<std::size_t>(gates_[q]) * stride + c;
      simd::store(gate, y_inf + (simd::load(gate, n) - y_inf) * E, n);
    }
  }
  if (clamped != 0) clamps_.fetch_add(clamped, std::memory_order_relaxed);
}

}  // namespace fibrodem
