// Evaluates a model on one block of cells that share an initial state except
// for V (one cell per given voltage): what the singularity tests of the ionic
// models look at.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
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
// `overrides`: parameters set after the variant's.
inline BlockResult evaluate_at_voltages(const CellModel& model, const std::vector<double>& voltages,
                                        const std::string& variant_name = "",
                                        const std::map<std::string, double>& overrides = {}) {
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
    if (auto it = overrides.find(p.name); it != overrides.end()) value = it->second;
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

// At a removable singularity V0, every a and b is finite and continuous: over
// 1e-7 mV a smooth rate changes by ~1e-7 x (its relative slope, < 1 /mV in
// these models), so 1e-6 of its size bounds any honest change; a wrong limit
// value (e.g. the CRN CellML's beta_xr fallback, off by 7e-4 relative) fails.
inline void check_continuous_at(const CellModel& model, double V0, const std::string& variant_name = "") {
  const double h = 1e-7;
  const BlockResult r = evaluate_at_voltages(model, {V0 - h, V0, V0 + h}, variant_name);
  const auto& states = model.info().states;
  for (std::size_t k = 0; k < states.size(); ++k) {
    CAPTURE(states[k].name);
    for (const auto* v : {&r.a, &r.b}) {
      const double lo = (*v)[k * r.n + 0], mid = (*v)[k * r.n + 1], hi = (*v)[k * r.n + 2];
      REQUIRE(std::isfinite(lo));
      REQUIRE(std::isfinite(mid));
      REQUIRE(std::isfinite(hi));
      const double scale = std::max({std::fabs(lo), std::fabs(mid), std::fabs(hi), 1e-300});
      CHECK(std::fabs(mid - lo) <= 1e-6 * scale);
      CHECK(std::fabs(hi - mid) <= 1e-6 * scale);
    }
  }
}

}  // namespace fibrodem::testing
