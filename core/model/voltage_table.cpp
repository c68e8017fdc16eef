#include "model/voltage_table.hpp"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "model/population.hpp"
#include "model/simd.hpp"
#include "model/voltage_table_cache.hpp"

namespace fibrodem {

std::shared_ptr<VoltageTable> VoltageTable::build(const Population& pop, double v_min_mV, double v_max_mV,
                                                  double step_mV) {
  if (pop.voltage_state < 0 || !(v_max_mV > v_min_mV) || !(step_mV > 0)) return nullptr;
  const auto& states = pop.info().states;
  bool any_gate = false;
  for (const auto& s : states) any_gate = any_gate || s.voltage_only;
  if (!any_gate) return nullptr;
  VoltageTableKey key = VoltageTableKey::of(pop, v_min_mV, v_max_mV, step_mV);
  auto& cache = VoltageTableCache::instance();
  if (auto rows = cache.find(key)) return std::make_shared<VoltageTable>(std::move(rows));

  auto table = std::make_shared<VoltageTableRows>();
  table->key = std::move(key);
  for (std::size_t k = 0; k < states.size(); ++k)
    if (states[k].voltage_only) table->gates.push_back(static_cast<int>(k));
  table->v_min = v_min_mV;
  table->step = step_mV;
  table->inv_step = 1.0 / step_mV;
  table->points = static_cast<std::size_t>(std::llround((v_max_mV - v_min_mV) / step_mV)) + 1;

  // The probe: one cell per table point, exact model (no table on the probe),
  // one block of points at a time, in the blocks a whole probe would be
  // evaluated in: the states of a block stay in the cache and are reused,
  // where a probe of every point (colman: 4001 cells, 3.5 MB) cost a
  // single-cell run more in fresh pages than the sampling itself. No outputs
  // (the rates never depend on them).
  const std::size_t n = table->points;
  const std::size_t g = table->gates.size();
  auto rows = std::make_shared<std::vector<double>>(n * 2 * g);
  Population probe;
  probe.type = pop.type;
  probe.model = pop.model;
  probe.params = pop.params;
  probe.initial_state = pop.initial_state;
  probe.voltage_state = pop.voltage_state;
  probe.scalar_reference = pop.scalar_reference;
  for (std::size_t first = 0; first < n; first += kCellsPerBlock) {
    const std::size_t m = std::min(kCellsPerBlock, n - first);
    probe.cells.resize(m);
    probe.reset();
    probe.outputs.clear();
    for (std::size_t c = 0; c < m; ++c)
      probe.state(pop.voltage_state, c) = v_min_mV + step_mV * static_cast<double>(first + c);
    probe.evaluate(0.0);
    for (std::size_t c = 0; c < m; ++c)
      for (std::size_t i = 0; i < g; ++i) {
        const std::size_t k = static_cast<std::size_t>(table->gates[i]);
        (*rows)[(first + c) * 2 * g + 2 * i] = probe.a[k * m + c];
        (*rows)[(first + c) * 2 * g + 2 * i + 1] = probe.b[k * m + c];
      }
  }
  table->rows = std::move(rows);
  return std::make_shared<VoltageTable>(cache.insert(std::move(table)));
}

void VoltageTable::fill(const BlockView& block, int voltage_state) const {
  const VoltageTableRows& d = *data_;
  const int* gates = d.gates.data();
  const double* rows = d.rows->data();
  const std::size_t g = d.gates.size(), width = 2 * g;
  const double* V = block.y + static_cast<std::size_t>(voltage_state) * block.stride;
  const std::size_t ab_stride = block.ab_stride ? block.ab_stride : block.stride;
  long long clamped = 0;
  for (std::size_t c = block.begin; c < block.end; ++c) {
    const auto [i, w] = position(d, V[c], clamped);
    const double* r0 = rows + i * width;
    const double* r1 = r0 + width;
    for (std::size_t q = 0; q < g; ++q) {
      const std::size_t at = static_cast<std::size_t>(gates[q]) * ab_stride + c;
      block.a[at] = r0[2 * q] + w * (r1[2 * q] - r0[2 * q]);
      block.b[at] = r0[2 * q + 1] + w * (r1[2 * q + 1] - r0[2 * q + 1]);
    }
  }
  if (clamped != 0) clamps_.fetch_add(clamped, std::memory_order_relaxed);
}

std::shared_ptr<VoltageTable> VoltageTable::with_rush_larsen_step(double dt_ms) const {
  const VoltageTableRows& d = *data_;
  VoltageTableKey key = d.key;
  key.rush_larsen_dt_ms = dt_ms;
  auto& cache = VoltageTableCache::instance();
  if (auto rows = cache.find(key)) return std::make_shared<VoltageTable>(std::move(rows));
  const std::vector<double>& ab = *d.rows;
  for (std::size_t r = 1; r < ab.size(); r += 2)
    if (ab[r] == 0.0) return nullptr;  // a gate standing still there has no y_inf
  auto t = std::make_shared<VoltageTableRows>(d);  // the a, b rows shared, not copied
  t->key = std::move(key);
  t->rl_dt = dt_ms;
  t->rl_rows.resize(ab.size());
  for (std::size_t r = 0; r < ab.size(); r += 2) {
    const double a = ab[r], b = ab[r + 1];
    t->rl_rows[r] = -a / b;
    t->rl_rows[r + 1] = std::exp(b * dt_ms);
  }
  return std::make_shared<VoltageTable>(cache.insert(std::move(t)));
}

namespace {

// A gate's y_inf and exp(b dt) at the two table points around each lane's V.
// The two values sit side by side in a row (rl_rows: [y_inf, E] per gate), so
// on AVX2 each lane's pair is one 16-byte load and four lanes are put
// together by two inserts and an unpack per row: cheaper than AVX2's four
// gathers (one per value), which Zen 3 issues as many micro-ops each.
// Elsewhere, gathers as before (AVX-512 could not be measured on this
// project's AVX2 machine). lane_at: each lane's row as an offset into the
// rows, in an aligned array.
[[gnu::always_inline]] inline void rows_of_gate(const double* column, const std::int64_t* lane_at, std::size_t width,
                                                simd::Real& y0, simd::Real& e0, simd::Real& y1, simd::Real& e1) {
#if defined(__AVX2__) && !defined(__AVX512F__)
  static_assert(simd::kLanes == 4);
  const auto pairs = [&](std::size_t offset, simd::Real& y, simd::Real& e) {
    // Lanes 0 and 2 in one register, 1 and 3 in the other (128-bit halves).
    const __m256d even = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(column + offset + lane_at[0])),
                                              _mm_loadu_pd(column + offset + lane_at[2]), 1);
    const __m256d odd = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(column + offset + lane_at[1])),
                                             _mm_loadu_pd(column + offset + lane_at[3]), 1);
    y = _mm256_unpacklo_pd(even, odd);  // (y_0, y_1, y_2, y_3)
    e = _mm256_unpackhi_pd(even, odd);
  };
  pairs(0, y0, e0);
  pairs(width, y1, e1);
#else
  const auto at = xsimd::batch<std::int64_t>::load_aligned(lane_at);
  y0 = simd::Real::gather(column, at);
  y1 = simd::Real::gather(column + width, at);
  e0 = simd::Real::gather(column + 1, at);
  e1 = simd::Real::gather(column + 1 + width, at);
#endif
}

}  // namespace

void VoltageTable::advance_gates(double* y, std::size_t stride, const double* V, std::size_t begin,
                                 std::size_t end) const {
  // In lanes of cells: each lane's table rows are gathered (every cell has its
  // own V), the rest is arithmetic on whole registers.
  using simd::Real;
  using Index = xsimd::batch<std::int64_t>;
  static_assert(Index::size == Real::size);
  const VoltageTableRows& d = *data_;
  const int* gates = d.gates.data();
  const double* rl_rows = d.rl_rows.data();
  const double v_min = d.v_min, inv_step = d.inv_step;
  const std::size_t points = d.points;
  const std::size_t g = d.gates.size(), width = 2 * g;
  const double last = static_cast<double>(points - 1);
  long long clamped = 0;
  for (std::size_t c = begin; c < end; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, end - c);
    // Table position, as position() does it: below the table or NaN -> row 0,
    // above -> the last row; both counted.
    Real x = (simd::load(V + c, n) - v_min) * inv_step;
    const auto below = !(x >= 0.0), above = x > last;
    alignas(64) bool out[simd::kLanes];
    (below | above).store_aligned(out);
    for (std::size_t i = 0; i < n; ++i) clamped += out[i];
    x = simd::select(below, 0.0, simd::select(above, last, x));
    const Index row = xsimd::min(xsimd::to_int(simd::floor(x)), Index(static_cast<std::int64_t>(points) - 2));
    const Real w = x - xsimd::to_float(row);
    const Index at = row * static_cast<std::int64_t>(width);
    alignas(64) std::int64_t lane_at[simd::kLanes];
    at.store_aligned(lane_at);
    for (std::size_t q = 0; q < g; ++q) {
      Real y0, y1, e0, e1;
      rows_of_gate(rl_rows + 2 * q, lane_at, width, y0, e0, y1, e1);
      const Real y_inf = y0 + w * (y1 - y0), E = e0 + w * (e1 - e0);
      double* gate = y + static_cast<std::size_t>(gates[q]) * stride + c;
      simd::store(gate, y_inf + (simd::load(gate, n) - y_inf) * E, n);
    }
  }
  if (clamped != 0) clamps_.fetch_add(clamped, std::memory_order_relaxed);
}

}  // namespace fibrodem
