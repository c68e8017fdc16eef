// A Population is the block of all cells of one cell type, run by one cell
// model: states, derivatives (a, b), inputs and outputs in structure-of-arrays
// layout, and one parameter vector for the block. The derivative arrays are
// there for integrators that read them whole (CVODE, fixed step); without
// them each block's a and b go to a scratch tile of its thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "model/cell_model.hpp"
#include "model/cell_type.hpp"
#include "model/voltage_table.hpp"
#include "model/work_split.hpp"

namespace fibrodem {

// Work on a block right after it was evaluated (an integrator's state update),
// while its derivatives are still in cache. The view is the block's alone:
// cells [0, end - begin) of it are the population's [begin, end); its a and b
// are a scratch tile of the thread (ab_stride), not the population's arrays.
using AfterBlock = std::function<void(const BlockView& block)>;

// What a model's evaluate() threw, if it did (the contract says it must not):
// recorded on the thread that caught it, re-thrown after the parallel loop.
struct ModelFault {
  std::atomic<bool> raised{false};
  std::mutex mutex;
  std::string message;
  void record(const std::string& what);
};

struct Population {
  CellType type = CellType::myocyte;
  std::shared_ptr<const CellModel> model;
  // Where the model was loaded from: its plugin file and that file's SHA-256
  // (empty for a model that came from no registry). Keys the table cache.
  std::string model_origin;
  std::string variant;
  std::vector<int> cells;  // each of its cells' number in the system (CellSystem::numbering)
  std::vector<double> params;
  std::vector<double> initial_state;  // per state (after the variant)
  std::vector<double> y, a, b, inputs, outputs;
  int voltage_state = -1;
  double capacitance_pF = 0;
  // Lookup table of the voltage_only gates' rates (solver.lookup_tables), or
  // null: evaluate() then calls the model with skip_voltage_only_gates and
  // fills those gates from the table. Built by use_lookup_table().
  std::shared_ptr<const VoltageTable> table;
  // Set by a Rush-Larsen integrator whose step the table has columns for: it
  // advances the tabulated gates from the table itself, so evaluate() leaves
  // their a, b unwritten.
  bool table_advances_gates = false;
  // solver.simd false: the models run one cell at a time in double.
  bool scalar_reference = false;
  // Per state, the range a value must stay in (the StateInfo bounds widened by
  // round-off), for integrators that check states as they update them; empty:
  // not checked there.
  std::vector<double> lower_limit, upper_limit;
  // State k's limits, unbounded where none were given.
  double lower_limit_of(std::size_t k) const {
    return lower_limit.empty() ? -std::numeric_limits<double>::infinity() : lower_limit[k];
  }
  double upper_limit_of(std::size_t k) const {
    return upper_limit.empty() ? std::numeric_limits<double>::infinity() : upper_limit[k];
  }

  const ModelInfo& info() const { return model->info(); }
  std::size_t size() const { return cells.size(); }
  std::size_t n_states() const { return info().states.size(); }

  // Sizes the arrays and puts every cell at the initial state; a and b only
  // with_derivatives (else they are freed: see has_derivatives()).
  void reset(bool with_derivatives = true);
  // Whether a and b hold every cell's derivatives. Without them, evaluate()
  // without `after` still writes the outputs; the derivatives are dropped.
  bool has_derivatives() const { return a.size() == n_states() * size() && b.size() == a.size(); }
  // Sizes a and b if they are not (for an integrator that reads them).
  void use_derivatives();
  double& state(int k, std::size_t local) { return y[k * size() + local]; }
  double state(int k, std::size_t local) const { return y[k * size() + local]; }
  double* voltage() { return y.data() + voltage_state * size(); }
  double* i_ext() { return inputs.data(); }  // input 0 of an ionic model
  // Evaluates a, b and outputs for the whole population at time t, block by
  // block (in parallel). With `after`, each block's a and b go to a scratch
  // tile handed to after() instead (the population's a, b are left alone, so
  // memory traffic stays that of the states), and the outputs are written
  // only if with_outputs. Without derivative arrays (has_derivatives()), the
  // tile is used without `after` too.
  void evaluate(double t_ms, const AfterBlock& after = nullptr, bool with_outputs = true);
  // The same for block k alone (cells [k, k+1) x kCellsPerBlock), on the calling thread.
  void evaluate_block(std::size_t k, double t_ms, const AfterBlock& after = nullptr, bool with_outputs = true) {
    evaluate_cells(k * kCellsPerBlock, std::min(size(), (k + 1) * kCellsPerBlock), t_ms, after, with_outputs);
  }
  // The same for cells [begin, end) of one block, on the calling thread (a
  // cell's results do not depend on which piece of its block it is in).
  void evaluate_cells(std::size_t begin, std::size_t end, double t_ms, const AfterBlock& after = nullptr,
                      bool with_outputs = true);
  std::size_t block_count() const { return (size() + kCellsPerBlock - 1) / kCellsPerBlock; }
  BlockView view();
  // Builds the table from the current parameters and initial state; false
  // (and no table) when the model has no voltage_only gates.
  bool use_lookup_table();
  // Throws PluginError naming the model and its message if its evaluate()
  // threw since the population was made (call after a parallel evaluation).
  void rethrow_model_fault() const;
  std::shared_ptr<ModelFault> fault = std::make_shared<ModelFault>();
};

// Index of a named state / parameter / output, or -1.
int find_state(const ModelInfo& info, const std::string& name);
int find_parameter(const ModelInfo& info, const std::string& name);
int find_output(const ModelInfo& info, const std::string& name);

}  // namespace fibrodem
