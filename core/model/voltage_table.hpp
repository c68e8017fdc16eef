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
  mutable std::atomic<long long> clamps_{0};
};

}  // namespace fibrodem
