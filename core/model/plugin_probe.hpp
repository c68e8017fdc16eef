// The probe harness of the plugin conformance checks (plugin_check.cpp): a
// block of cells laid out as the core lays it out, its result arrays poisoned
// so that an entry evaluate() never wrote is seen, and the settings
// (defaults, then each variant) the checks run a model under.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "model/cell_model.hpp"

namespace fibrodem::plugin_probe {

// A value no model computes: a quiet NaN with a payload of our own. An entry
// that still holds it after evaluate() was never written.
double poison();
bool is_poison(double v);
bool same_bits(double x, double y);

// A block of cells in structure-of-arrays layout, as the core lays it out.
struct Probe {
  const CellModel& model;
  const ModelInfo& info;
  std::size_t n;
  std::vector<double> params, y, a, b, inputs, outputs;

  Probe(const CellModel& m, std::size_t cells, const std::vector<double>& parameters,
        const std::vector<double>& initial, double input0)
      : model(m), info(m.info()), n(cells), params(parameters) {
    y.resize(info.states.size() * n);
    for (std::size_t k = 0; k < info.states.size(); ++k)
      for (std::size_t c = 0; c < n; ++c) y[k * n + c] = initial[k];
    inputs.assign(std::max<std::size_t>(1, info.inputs.size()) * n, 0.0);
    std::fill(inputs.begin(), inputs.begin() + static_cast<long>(n), input0);
    a.assign(info.states.size() * n, poison());
    b = a;
    outputs.assign(info.outputs.size() * n, poison());
  }
  double& state(std::size_t k, std::size_t c) { return y[k * n + c]; }
  double rate(std::size_t k, std::size_t c) const { return a[k * n + c] + b[k * n + c] * y[k * n + c]; }
  void poison_results() {
    std::fill(a.begin(), a.end(), poison());
    std::fill(b.begin(), b.end(), poison());
    std::fill(outputs.begin(), outputs.end(), poison());
  }
  void evaluate(std::size_t begin, std::size_t end, bool scalar, bool skip_voltage_only = false, double t_ms = 0) {
    BlockView v;
    v.begin = begin;
    v.end = end;
    v.stride = v.ab_stride = n;
    v.y = y.data();
    v.params = params.data();
    v.inputs = inputs.data();
    v.a = a.data();
    v.b = b.data();
    v.outputs = outputs.empty() ? nullptr : outputs.data();
    v.skip_voltage_only_gates = skip_voltage_only;
    v.scalar_reference = scalar;
    model.evaluate(v, t_ms);
  }
  void evaluate_all(bool scalar = false) { evaluate(0, n, scalar); }
};

// The default parameters and initial state, then each variant on top of them.
struct Setting {
  std::string label;
  std::vector<double> params, initial;
};

std::vector<Setting> settings_of(const ModelInfo& info);

// Input 0 at rest: no external current for an ionic model, a diastolic
// 0.1 uM Ca_i for a myofilament model.
double rest_input(const ModelInfo& info);
// An ionic model with a membrane potential state.
bool ionic(const ModelInfo& info);
// Another value of a state within its bounds, clearly different.
double moved(const StateInfo& s, double value);

}  // namespace fibrodem::plugin_probe
