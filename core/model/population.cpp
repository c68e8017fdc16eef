#include "model/population.hpp"

#include <algorithm>

#include "model/plugin_registry.hpp"

namespace fibrodem {

void ModelFault::record(const std::string& what) {
  std::lock_guard<std::mutex> lock(mutex);
  if (!raised.exchange(true)) message = what;  // the first one
}

void Population::rethrow_model_fault() const {
  if (fault->raised.load())
    throw PluginError("model " + info().name + " (" + cell_type_name(type) + ") threw from evaluate(): " +
                      fault->message + " (a model must not throw; the run stops here)");
}

void Population::reset(bool with_derivatives) {
  const std::size_t n = size();
  y.assign(n_states() * n, 0.0);
  if (with_derivatives) {
    a.assign(n_states() * n, 0.0);
    b.assign(n_states() * n, 0.0);
  } else {
    std::vector<double>().swap(a);
    std::vector<double>().swap(b);
  }
  inputs.assign(std::max<std::size_t>(1, info().inputs.size()) * n, 0.0);
  outputs.assign(info().outputs.size() * n, 0.0);
  for (std::size_t k = 0; k < n_states(); ++k)
    for (std::size_t c = 0; c < n; ++c) y[k * n + c] = initial_state[k];
}

void Population::use_derivatives() {
  if (has_derivatives()) return;
  a.assign(n_states() * size(), 0.0);
  b.assign(n_states() * size(), 0.0);
}

BlockView Population::view() {
  BlockView v;
  v.begin = 0;
  v.end = size();
  v.stride = size();
  v.y = y.data();
  v.params = params.data();
  v.inputs = inputs.data();
  v.a = a.empty() ? nullptr : a.data();
  v.b = b.empty() ? nullptr : b.data();
  v.outputs = outputs.empty() ? nullptr : outputs.data();
  v.ab_stride = size();
  v.scalar_reference = scalar_reference;
  return v;
}

void Population::evaluate(double t_ms, const AfterBlock& after, bool with_outputs) {
  // Blocks of cells in parallel: each cell's derivatives depend only on its own
  // state and inputs, so the result does not depend on the thread count.
  for_each_block(static_cast<long>(block_count()),
                 [&](long k) { evaluate_block(static_cast<std::size_t>(k), t_ms, after, with_outputs); });
  rethrow_model_fault();
}

void Population::evaluate_cells(std::size_t begin, std::size_t end, double t_ms, const AfterBlock& after,
                                bool with_outputs) {
  BlockView block = view();
  if (after || !has_derivatives()) {
    // The block's own view: cells from 0, a and b in this thread's tile.
    // (Grown, never shrunk: the populations share it, and resize() back up
    // to the larger one's size zeroed it at every block, 1.5 % of the Fig. 3
    // EM scene's time.)
    thread_local std::vector<double> tile;
    const std::size_t tile_size = 2 * n_states() * kCellsPerBlock;
    if (tile.size() < tile_size) tile.resize(tile_size);
    block.y += begin;
    block.inputs += begin;
    block.outputs = with_outputs && block.outputs ? block.outputs + begin : nullptr;
    block.a = tile.data();
    block.b = tile.data() + n_states() * kCellsPerBlock;
    block.ab_stride = kCellsPerBlock;
    block.begin = 0;
    block.end = end - begin;
  } else {
    block.begin = begin;
    block.end = end;
  }
  // An exception must not leave an OpenMP region (that would terminate the
  // process): it is recorded and re-thrown after the loop.
  try {
    block.skip_voltage_only_gates = table != nullptr;
    model->evaluate(block, t_ms);
  } catch (const std::exception& e) {
    return fault->record(e.what());
  } catch (...) {
    return fault->record("an exception that is not a std::exception");
  }
  if (table && !table_advances_gates) table->fill(block, voltage_state);
  if (after) after(block);
}

bool Population::use_lookup_table() {
  table = VoltageTable::build(*this);
  return table != nullptr;
}

namespace {
template <class List>
int find_named(const List& list, const std::string& name) {
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == name) return static_cast<int>(i);
  return -1;
}
}  // namespace

int find_state(const ModelInfo& info, const std::string& name) { return find_named(info.states, name); }
int find_parameter(const ModelInfo& info, const std::string& name) {
  return find_named(info.parameters, name);
}
int find_output(const ModelInfo& info, const std::string& name) { return find_named(info.outputs, name); }

}  // namespace fibrodem
