// A process-wide, bounded cache of lookup-table rows (model/voltage_table.hpp).
//
// Sampling colman's gates on 4001 potentials and adding the Rush-Larsen columns
// costs ~2 ms, which a calibration loop of thousands of single-cell runs
// (fibrodem.simulate_cell), a sweep's points or a comparison would pay on every
// run. The rows are immutable once built, so runs that would sample the same
// values share them; each run keeps its own clamp counter (VoltageTable).
//
// The key is everything that determines the sampled values, compared exactly
// (doubles bit for bit, never through a hash alone). The cache holds at most
// kBudgetBytes of rows, least recently used first out; look-up and insertion
// take a mutex (once per population per run, never in a hot loop).
#pragma once

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "model/cell_model.hpp"

namespace fibrodem {

struct Population;

// What a table's rows were sampled from.
struct VoltageTableKey {
  // The model as loaded: name, version and the plugin file's path and SHA-256
  // (Population::model_origin). A model that came from no registry (tests,
  // benchmarks) has no origin: its object's address stands in, and the key
  // keeps the object alive so that no other model can take that address while
  // the entry lives.
  std::string model_name, model_version, model_origin;
  std::shared_ptr<const CellModel> model_kept;  // only without an origin
  int cell_type = 0;
  int voltage_state = -1;
  bool scalar_reference = false;  // solver.simd false: the probe runs the scalar path
  // The probe block's parameters and states; its inputs are always zero (reset()).
  std::vector<double> params, initial_state;
  double v_min_mV = 0, v_max_mV = 0, step_mV = 0;
  double rush_larsen_dt_ms = 0;  // 0: the a, b rows alone

  static VoltageTableKey of(const Population& pop, double v_min_mV, double v_max_mV, double step_mV);
  // Bit-for-bit equality of every field (the model compared by origin, or by
  // address without one).
  bool same_as(const VoltageTableKey& other) const;
};

struct VoltageTableRows;

class VoltageTableCache {
 public:
  static constexpr std::size_t kBudgetBytes = 16u << 20;  // colman: ~0.7 MB of a, b, ~1.4 MB with RL columns

  static VoltageTableCache& instance();

  // The rows stored under `key`, or null (counted as a hit or a miss).
  std::shared_ptr<const VoltageTableRows> find(const VoltageTableKey& key);
  // Stores `rows` (whose key they carry) and returns what is stored under that
  // key afterwards: the rows already there if another thread was first.
  // Rows larger than the budget are returned without being stored.
  std::shared_ptr<const VoltageTableRows> insert(std::shared_ptr<const VoltageTableRows> rows);

  void clear();
  std::size_t bytes() const;
  std::size_t entries() const;
  long long hits() const;
  long long misses() const;

 private:
  mutable std::mutex mutex_;
  std::list<std::shared_ptr<const VoltageTableRows>> lru_;  // most recently used first
  std::size_t bytes_ = 0;
  long long hits_ = 0, misses_ = 0;
};

}  // namespace fibrodem
