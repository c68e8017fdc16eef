// Helpers shared by the CellML importer's test suites: where the test models
// and the plugins built from them are, loading those plugins, and one cell's
// rates as a plugin returns them.
#pragma once

#include <doctest/doctest.h>

#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "model/plugin_registry.hpp"

namespace fibrodem::testing {

// tests/cellml, and the plugins tests/CMakeLists.txt imports from it at build time.
inline const std::filesystem::path kCellml = std::filesystem::path(FIBRODEM_SOURCE_DIR) / "tests" / "cellml";
inline const std::filesystem::path kGenerated = std::filesystem::path(FIBRODEM_BINARY_DIR) / "cellml_plugins";

inline std::shared_ptr<const CellModel> load(const std::string& name) {
  static PluginRegistry registry({kGenerated});
  return registry.load(name);
}

inline int index_of(const std::vector<StateInfo>& states, const std::string& name) {
  for (std::size_t k = 0; k < states.size(); ++k)
    if (states[k].name == name) return static_cast<int>(k);
  FAIL("no state " << name);
  return -1;
}

inline int output_of(const ModelInfo& info, const std::string& name) {
  for (std::size_t k = 0; k < info.outputs.size(); ++k)
    if (info.outputs[k].name == name) return static_cast<int>(k);
  FAIL("no output " << name);
  return -1;
}

// One cell's rates dy/dt = a + b y as the plugin returns them, and its outputs.
struct Rates {
  std::vector<double> dydt, outputs;
};

// The model's default parameters, its one input i_ext; in SIMD lanes or the
// scalar reference path.
inline Rates evaluate(const CellModel& model, const std::vector<double>& y, double t_ms, double i_ext_pA,
                      bool lanes) {
  const auto& info = model.info();
  std::vector<double> params, a(y.size()), b(y.size()), inputs{i_ext_pA}, outputs(info.outputs.size());
  for (const auto& p : info.parameters) params.push_back(p.default_value);
  BlockView v;
  v.begin = 0;
  v.end = 1;
  v.stride = 1;
  v.y = y.data();
  v.params = params.data();
  v.inputs = inputs.data();
  v.a = a.data();
  v.b = b.data();
  v.outputs = outputs.data();
  v.scalar_reference = !lanes;
  model.evaluate(v, t_ms);
  Rates r{std::vector<double>(y.size()), outputs};
  for (std::size_t k = 0; k < y.size(); ++k) r.dydt[k] = a[k] + b[k] * y[k];
  return r;
}

// One classic RK4 step of dy/dt = f(t, y) (the same method on a plugin and on a
// right-hand side written by hand, so the two differ by round-off alone).
template <std::size_t N, class F>
void rk4(std::array<double, N>& y, double t, double dt, F f) {
  auto add = [](std::array<double, N> x, const std::array<double, N>& k, double h) {
    for (std::size_t i = 0; i < N; ++i) x[i] += h * k[i];
    return x;
  };
  const auto k1 = f(t, y), k2 = f(t + dt / 2, add(y, k1, dt / 2)), k3 = f(t + dt / 2, add(y, k2, dt / 2)),
             k4 = f(t + dt, add(y, k3, dt));
  for (std::size_t i = 0; i < N; ++i) y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

// A generated source without the lines that name the file and its CellML
// version (the 1.0, 1.1 and 2.0 forms of a model give the same rest).
inline std::string without_origin(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line))
    if (line.find(".cellml") == std::string::npos && line.find("CellML 1.") == std::string::npos &&
        line.find("CellML 2.") == std::string::npos)
      out += line + "\n";
  return out;
}

}  // namespace fibrodem::testing
