// A population without its own a and b arrays (Population::reset(false)):
// evaluate() still writes the outputs, and every integrator gives the bits it
// gives with the arrays, the ones that read them sizing them themselves.
#include <doctest/doctest.h>

#include <limits>
#include <random>
#include <string>
#include <vector>

#include "integrate/integrator.hpp"
#include "model/plugin_registry.hpp"
#include "model/population.hpp"

using namespace fibrodem;

namespace {

std::shared_ptr<const CellModel> load(const std::string& name) {
  static PluginRegistry registry;
  return registry.load(name);
}

// n colman cells at its defaults, V spread over [-90, 20] mV at random (the
// same for every call), with or without the derivative arrays.
Population random_block(std::size_t n, bool with_derivatives) {
  Population pop;
  pop.model = load("colman");
  for (const auto& p : pop.info().parameters) pop.params.push_back(p.default_value);
  for (const auto& s : pop.info().states) pop.initial_state.push_back(s.initial);
  pop.voltage_state = pop.info().voltage_state;
  pop.cells.resize(n);
  for (std::size_t c = 0; c < n; ++c) pop.cells[c] = static_cast<int>(c);
  pop.reset(with_derivatives);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> V(-90, 20);
  for (std::size_t c = 0; c < n; ++c) pop.state(pop.voltage_state, c) = V(rng);
  return pop;
}

struct Unobserved : StepObserver {
  double next_sample_ms() const override { return std::numeric_limits<double>::infinity(); }
  void on_sample(double) override {}
  void on_step(double, double, const double*) override {}
};

// The cells' states after `method` from 0 to 3 ms, uncoupled.
Population advanced(const std::string& method, bool with_derivatives, bool* had_derivatives_after) {
  CellSystem system;
  system.populations.push_back(random_block(300, with_derivatives));
  system.numbering = CellNumbering(300);
  for (std::size_t c = 0; c < 300; ++c) system.where.push_back({0, static_cast<std::uint32_t>(c)});
  system.V_mV.assign(300, 0.0);
  system.i_ext_pA.assign(300, 0.0);
  SolverSpec solver;
  solver.method = method;
  solver.dt_ms = 0.005;
  Unobserved unobserved;
  make_integrator(solver)->advance(system, 0.0, 3.0, unobserved);
  *had_derivatives_after = system.populations.front().has_derivatives();
  return system.populations.front();
}

}  // namespace

TEST_CASE("population without derivative arrays: evaluate() writes the outputs of one with them") {
  // 300 cells: whole blocks and a part of one (kCellsPerBlock).
  Population with = random_block(300, true), without = random_block(300, false);
  CHECK(with.has_derivatives());
  CHECK_FALSE(without.has_derivatives());
  CHECK(without.a.empty());
  with.evaluate(0.0);
  without.evaluate(0.0);
  CHECK_FALSE(without.has_derivatives());  // not allocated on the way
  REQUIRE_FALSE(with.outputs.empty());
  CHECK(without.outputs == with.outputs);  // bit for bit
  CHECK(without.y == with.y);
}

TEST_CASE("population without derivative arrays: each integrator gives the same bits") {
  for (const auto& entry : integrators()) {
    const std::string method = entry.name;
    CAPTURE(method);
    bool with_after = false, without_after = false;
    const Population with = advanced(method, true, &with_after);
    const Population without = advanced(method, false, &without_after);
    CHECK(with_after);
    // An integrator that reads the arrays sizes them; the others never do.
    CHECK(without_after == reads_population_derivatives(method));
    CHECK(without.y == with.y);
    // The cells moved (a step was taken): V differs from the random start.
    const Population start = random_block(300, true);
    CHECK(without.y != start.y);
  }
  CHECK(reads_population_derivatives("no such method"));  // unknown: the safe answer
}
