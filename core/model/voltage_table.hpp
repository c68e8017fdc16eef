// Lookup tables of voltage-dependent gate rates (openCARP LIMPET style).
//
// A gate the model marks voltage_only (StateInfo) has a and b that depend only
// on V and the population's parameters. A VoltageTable samples them once, on a
// probe block spanning V_min..V_max every dV (other states at the initial
// state, the population's parameters), and afterwards fills a, b of those gates
// by linear interpolation in V while the model is called with
// skip_voltage_only_gates = true, which saves the model their exp() calls.
// Outside the table V is clamped to its ends; clamps are counted.
//
// The sampled rows are immutable and shared between runs through a process-wide
// cache (model/voltage_table_cache.hpp); a VoltageTable is one population's use
// of them, with its own clamp counter.
#pragma once

#include <atomic>
#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "model/cell_model.hpp"
#include "model/voltage_table_cache.hpp"

namespace fibrodem {

struct Population;

// The sampled values of one table, and what they were sampled from.
struct VoltageTableRows {
  VoltageTableKey key;
  double v_min = 0, step = 1, inv_step = 1;
  std::size_t points = 0;
  std::vector<int> gates;  // tabulated state indices
  // Row i (V = v_min + i*step): a, b of each gate in turn, 2 * gates.size() values
  // (one copy, shared with the rows that add the Rush-Larsen columns to them).
  std::shared_ptr<const std::vector<double>> rows;
  // The same rows for y_inf, E (with_rush_larsen_step), and their step (0: none).
  std::vector<double> rl_rows;
  double rl_dt = 0;
};

class VoltageTable {
 public:
  static constexpr double kDefaultMin_mV = -120.0, kDefaultMax_mV = 80.0, kDefaultStep_mV = 0.05;

  // Null when the population has no membrane potential or its model marks no
  // voltage_only gate. Rows sampled before for the same key come from the cache.
  static std::shared_ptr<VoltageTable> build(const Population& pop, double v_min_mV = kDefaultMin_mV,
                                             double v_max_mV = kDefaultMax_mV,
                                             double step_mV = kDefaultStep_mV);

  // Fills a, b of the tabulated gates for the cells [begin, end) of the block
  // from the states' V (state voltage_state). Thread-safe on disjoint blocks.
  void fill(const BlockView& block, int voltage_state) const;

  // Rush-Larsen columns for a fixed step dt (openCARP does the same): per gate
  // y_inf(V) = -a/b and E(V) = exp(b dt), so that the update
  //     y' = y_inf + (y - y_inf) E
  // costs no exp() either. Returns a new table (clamp count 0) with them added,
  // from the cache when they were computed before, or null if some tabulated
  // gate has b = 0 somewhere (no y_inf there).
  std::shared_ptr<VoltageTable> with_rush_larsen_step(double dt_ms) const;
  // The step the Rush-Larsen columns were built for (0: none).
  double rush_larsen_step_ms() const { return data_->rl_dt; }
  // Advances the tabulated gates of the cells [begin, end) over rush_larsen_step_ms()
  // from the potentials V (the step's start): gate row k at y + k * stride.
  void advance_gates(double* y, std::size_t stride, const double* V, std::size_t begin, std::size_t end) const;

  const std::vector<int>& gates() const { return data_->gates; }  // tabulated state indices
  std::size_t points() const { return data_->points; }
  double v_min() const { return data_->v_min; }
  double v_max() const { return data_->v_min + data_->step * static_cast<double>(data_->points - 1); }
  double step() const { return data_->step; }
  // Cell evaluations whose V lay outside the table (or was NaN) so far.
  long long clamp_count() const { return clamps_.load(std::memory_order_relaxed); }
  // The shared rows (two tables with the same key hold the same object).
  const std::shared_ptr<const VoltageTableRows>& rows() const { return data_; }

  explicit VoltageTable(std::shared_ptr<const VoltageTableRows> data) : data_(std::move(data)) {}

 private:
  std::shared_ptr<const VoltageTableRows> data_;
  // Table position of potential V (clamped to the ends, counted): row, weight.
  struct Position {
    std::size_t row;
    double weight;
  };
  static Position position(const VoltageTableRows& d, double V, long long& clamped) {
    const double last = static_cast<double>(d.points - 1);
    double x = (V - d.v_min) * d.inv_step;
    if (!(x >= 0.0)) {  // below the table, or NaN
      x = 0.0;
      ++clamped;
    } else if (x > last) {
      x = last;
      ++clamped;
    }
    std::size_t i = static_cast<std::size_t>(x);
    if (i + 1 >= d.points) i = d.points - 2;
    return {i, x - static_cast<double>(i)};
  }
  mutable std::atomic<long long> clamps_{0};
};

}  // namespace fibrodem
