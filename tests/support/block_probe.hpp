// Evaluates a model on one block of cells that share an initial state except
// for V (one cell per given voltage): what the singularity tests of the ionic
// models look at.
#pragma once

#include <string>
#include <vector>

#include "model/cell_model.hpp"

namespace fibrodem::testing {

struct BlockResult {
  std::vector<double> a, b;
  std::size_t n = 0;
  double a_of(int k, std::size_t c) const { return a[k * n + c]; }
  double b_of(int k, std::size_t c) const { return b[k * n + c]; }
};

// The variant's parameters and initial state (the model's defaults for "").
inline BlockResult evaluate_at_voltages(const CellModel& model, const std::vector<double>& voltages,
                                        const std::string& variant_name = "") {
  const ModelInfo& info = model.info();
  const VariantInfo* variant = nullptr;
  for (const auto& v : info.variants)
    if (v.name == variant_name) variant = &v;
  const std::size_t n = voltages.size(), ns = info.states.size();
  std::vector<double> y(ns * n), params, inputs(info.inputs.size() * n, 0.0);
  for (std::size_t k = 0; k < ns; ++k) {
    double y0 = info.states[k].initial;
    if (variant)
      if (auto it = variant->initial_state.find(info.states[k].name); it != variant->initial_state.end())
        y0 = it->second;
    for (std::size_t c = 0; c < n; ++c) y[k * n + c] = y0;
  }
  for (std::size_t c = 0; c < n; ++c) y[info.voltage_state * n + c] = voltages[c];
  for (const auto& p : info.parameters) {
    double value = p.default_value;
    if (variant)
      if (auto it = variant->parameters.find(p.name); it != variant->parameters.end()) value = it->second;
    params.push_back(value);
  }
  BlockResult r;
  r.n = n;
  r.a.assign(ns * n, 0.0);
  r.b.assign(ns * n, 0.0);
  std::vector<double> outputs(info.outputs.size() * n, 0.0);
  BlockView block{0, n, n, y.data(), params.data(), inputs.data(), r.a.data(), r.b.data(), outputs.data()};
  model.evaluate(block, 0.0);
  return r;
}

}  // namespace fibrodem::testing
