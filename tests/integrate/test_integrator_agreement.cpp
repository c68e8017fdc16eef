// The three integrators agree on each model (CVODE at tight tolerance
// against Rush-Larsen at 0.005 ms and forward Euler at 0.001 ms, APD90 within
// 1 ms), on a myocyte coupled to a fibroblast so that both cell models are
// exercised by an action potential.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

json pair_scene(const std::string& myocyte, const std::string& variant, const std::string& fibroblast) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "agreement", "duration_ms": 500,
    "tissue": {"builder": "cell_pair", "fibroblasts": 1},
    "coupling": {"D_f_nS": 2},
    "stimulus": [{"target": "myocyte", "start_ms": 20, "duration_ms": 2, "amplitude_pA": 2000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  m["cells"]["myocyte"] = {{"model", myocyte}};
  if (!variant.empty()) m["cells"]["myocyte"]["variant"] = variant;
  m["cells"]["fibroblast"] = {{"model", fibroblast}};
  return m;
}

std::vector<BeatBiomarkers> run_with(json m, const json& solver) {
  m["solver"] = solver;
  Simulation sim(parse_scene(m));
  sim.run();
  return sim.biomarkers();
}

void check_agreement(const json& scene) {
  const auto cvode = run_with(scene, {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-9}});
  const auto rl = run_with(scene, {{"method", "rush_larsen"}, {"dt_ms", 0.005}});
  const auto euler = run_with(scene, {{"method", "euler"}, {"dt_ms", 0.001}});
  REQUIRE(cvode.size() == 2);
  REQUIRE(rl.size() == 2);
  REQUIRE(euler.size() == 2);
  for (std::size_t c = 0; c < 2; ++c) {
    CAPTURE(c);
    REQUIRE(std::isfinite(cvode[c].apd90_ms));
    CHECK(std::abs(rl[c].apd90_ms - cvode[c].apd90_ms) < 1.0);
    CHECK(std::abs(euler[c].apd90_ms - cvode[c].apd90_ms) < 1.0);
    CHECK(std::abs(rl[c].apo_mV - cvode[c].apo_mV) < 0.5);
    CHECK(std::abs(euler[c].apo_mV - cvode[c].apo_mV) < 0.5);
  }
}

}  // namespace

TEST_CASE("integrators agree: courtemanche with maleckar_active2" * doctest::test_suite("slow")) {
  check_agreement(pair_scene("courtemanche", "paced_1hz", "maleckar_active2"));
}

TEST_CASE("integrators agree: courtemanche with passive_fibroblast" * doctest::test_suite("slow")) {
  check_agreement(pair_scene("courtemanche", "paced_1hz", "passive_fibroblast"));
}

TEST_CASE("integrators agree: colman (colman2013) with maleckar_active2" * doctest::test_suite("slow")) {
  check_agreement(pair_scene("colman", "colman2013", "maleckar_active2"));
}

TEST_CASE("integrators agree: colman (ni2017) with passive_fibroblast" * doctest::test_suite("slow")) {
  check_agreement(pair_scene("colman", "ni2017", "passive_fibroblast"));
}

TEST_CASE("second-order Rush-Larsen at 0.02 ms is closer to CVODE than first order at 0.02 ms (APD90 and APO)") {
  const json scene = pair_scene("courtemanche", "paced_1hz", "maleckar_active2");
  const auto cvode = run_with(scene, {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-9}});
  const auto rl = run_with(scene, {{"method", "rush_larsen"}, {"dt_ms", 0.02}});
  const auto rl2 = run_with(scene, {{"method", "rush_larsen2"}, {"dt_ms", 0.02}});
  const double err_rl = std::abs(rl[0].apd90_ms - cvode[0].apd90_ms) + std::abs(rl[0].apo_mV - cvode[0].apo_mV);
  const double err_rl2 = std::abs(rl2[0].apd90_ms - cvode[0].apd90_ms) + std::abs(rl2[0].apo_mV - cvode[0].apo_mV);
  CAPTURE(err_rl);
  CAPTURE(err_rl2);
  CHECK(err_rl2 < err_rl);
  CHECK(std::abs(rl2[0].apd90_ms - cvode[0].apd90_ms) < 1.0);
}

TEST_CASE("CVODE at tissue scale: GMRES with the per-cell block preconditioner agrees with the banded direct solver") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "krylov", "duration_ms": 40,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 20},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0, 1], "start_ms": 1, "duration_ms": 2, "amplitude_pA": 8000}],
    "output": {"traces": {"cells": [19], "variables": ["V"], "every_ms": 0.5}}
  })");
  auto run_solver = [&](const std::string& linear_solver) {
    m["solver"] = {{"method", "cvode"}, {"rtol", 1e-7}, {"atol", 1e-9}, {"linear_solver", linear_solver}};
    Simulation sim(parse_scene(m));
    sim.run();
    CHECK(sim.integrator_description().find(linear_solver == "band" ? "band" : "GMRES") != std::string::npos);
    return sim.biomarkers();
  };
  const auto band = run_solver("band");
  const auto krylov = run_solver("krylov");
  REQUIRE(band.size() == 20);
  REQUIRE(krylov.size() == 20);
  for (std::size_t c = 0; c < 20; ++c) {
    CAPTURE(c);
    // Both solve the same BDF systems to CVODE's tolerance: activation times agree to ~1 us.
    CHECK(std::abs(band[c].activation_ms - krylov[c].activation_ms) < 0.01);
    CHECK(std::abs(band[c].apo_mV - krylov[c].apo_mV) < 0.05);
  }
}

// A one-cell population fills one SIMD lane of kLanes, so CVODE evaluates it
// on the scalar path (integrate/cvode_integrator.cpp): solver.simd then
// changes nothing, bit for bit; on the SIMD path the rounding of the vector
// exp and the scalar one would differ and CVODE's steps with them.
TEST_CASE("CVODE on one cell: the same trace with solver.simd true and false") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "one_cell_cvode", "duration_ms": 400,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "courtemanche"}},
    "stimulus": [{"target": "myocyte", "start_ms": 20, "duration_ms": 2, "amplitude_pA": 2000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 0.5}}
  })");
  std::vector<double> trace[2];
  for (int simd : {0, 1}) {
    m["solver"] = {{"method", "cvode"}, {"rtol", 1e-6}, {"atol", 1e-8}, {"simd", simd == 1}};
    Simulation sim(parse_scene(m));
    sim.run();
    trace[simd] = sim.trace("V", 0);
  }
  REQUIRE(trace[0].size() == 801);
  CHECK(*std::max_element(trace[1].begin(), trace[1].end()) > 0.0);  // an action potential
  CHECK(trace[0] == trace[1]);
}
