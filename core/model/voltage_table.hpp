// Lookup tables of voltage-dependent gate rates (openCARP LIMPET style).
//
// A gate the model marks voltage_only (StateInfo) has a and b that depend only
// on V and the population's parameters. A VoltageTable samples them once, on a
// probe block spanning V_min..V_max every dV (other states at the initial
// state, the population's parameters), and afterwards fills a, b of those gates
// by linear interpolation in V while the model is called with
// skip_voltage_only_gates = true, which saves the model their exp() calls.
// Outside the table V is clamped to its ends; clamps are counted.
#pragma once

#include <atomic>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "model/cell_model.hpp"

namespace fibrodem {

struct Population;

class VoltageTable {
 public:
  static constexpr double kDefaultMin_mV = -120.0, kDefaultMax_mV = 80.0, kDefaultStep_mV = 0.05;

  // Null when the population has no membrane potential or its model marks no
  // voltage_only gate.
  static std::shared_ptr<VoltageTable> build(const Population& pop, double v_min_mV = kDefaultMin_mV,
                                             double v_max_mV = kDefaultMax_mV,
                                             double step_mV = kDefaultStep_mV);

  // Fills a, b of the tabulated gates for the cells [begin, end) of the block
  // from the states' V (state voltage_state). Thread-safe on disjoint blocks.
  void fill(const BlockView& block, int voltage_state) const;

  // Rush-Larsen columns for a fixed step dt (openCARP does the same): per gate
  // y_inf(V) = -a/b and E(V) = exp(b dt), so that the update
  //     y' = y_inf + (y - y_inf) E
  // costs no exp() either. Returns a copy of this table with them added, or
  // null if some tabulated gate has b = 0 somewhere (no y_inf there).
  std::shared_ptr<VoltageTable> with_rush_larsen_step(double dt_ms) const;
  // The step the Rush-Larsen columns were built for (0: none).
  double rush_larsen_step_ms() const { return rl_dt_; }
  // Advances the tabulated gates of the cells [begin, end) over rush_larsen_step_ms()
  // from the potentials V (the step's start): gate row k at y + k * stride.
  void advance_gates(double* y, std::size_t stride, const double* V, std::size_t begin, std::size_t end) const;

  const std::vector<int>& gates() const { return gates_; }  // tabulated state indices
  std::size_t points() const { return points_; }
  double v_min() const { return v_min_; }
  double v_max() const { return v_min_ + step_ * static_cast<double>(points_ - 1); }
  double step() const { return step_; }
  // Cell evaluations whose V lay outside the table (or was NaN) so far.
  long long clamp_count() const { return clamps_.load(std::memory_order_relaxed); }

 private:
  double v_min_ = 0, step_ = 1, inv_step_ = 1;
  std::size_t points_ = 0;
  std::vector<int> gates_;
  // Row i (V = v_min + i*step): a, b of each gate in turn, 2 * gates_.size() values.
  std::vector<double> rows_;
  // The same rows for y_inf, E (with_rush_larsen_step), and their step.
  std::vector<double> rl_rows_;
  double rl_dt_ = 0;
  // Table position of potential V (clamped to the ends, counted): row, weight.
  struct Position {
    std::size_t row;
    double weight;
  };
  Position position(double V, long long& clamped) const {
    const double last = static_cast<double>(points_ - 1);
    double x = (V - v_min_) * inv_step_;
    if (!(x >= 0.0)) {  // below the table, or NaN
      x = 0.0;
      ++clamped;
    } else if (x > last) {
      x = last;
      ++clamped;
    }
    std::size_t i = static_cast<std::size_t>(x);
    if (i + 1 >= points_) i = points_ - 2;
    return {i, x - static_cast<double>(i)};
  }
  mutable std::atomic<long long> clamps_{0};
};

}  // namespace fibrodem
