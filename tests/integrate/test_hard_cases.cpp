// Hard cases: each scene stays stable, or stops with a clear error; never a
// silent NaN.
#include <doctest/doctest.h>

#include <cmath>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
json courtemanche_pair(int fibroblasts, const std::string& fibroblast_model, double D_f_nS) {
  return json::parse(R"({
    "fibrodem": 1, "name": "hard", "duration_ms": 400,
    "tissue": {"builder": "cell_pair", "fibroblasts": )" + std::to_string(fibroblasts) + R"(},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"},
              "fibroblast": {"model": ")" + fibroblast_model + R"("}},
    "coupling": {"D_f_nS": )" + std::to_string(D_f_nS) + R"(},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 1], "variables": ["V"], "every_ms": 1}}
  })");
}

std::vector<BeatBiomarkers> run(const json& m) {
  Simulation sim(parse_scene(m));
  sim.run();
  return sim.biomarkers();
}
}  // namespace

TEST_CASE("forward Euler past its limit stops early, naming the estimated limit and a stable step") {
  json m = courtemanche_pair(1, "passive_fibroblast", 2);
  m["solver"] = {{"method", "euler"}, {"dt_ms", 0.1}};
  try {
    run(m);
    FAIL("expected a blow-up");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.find("blow-up at t = 0.") != std::string::npos);  // within the first ms
    CHECK(message.find("estimated explicit stability limit") != std::string::npos);
    CHECK(message.find("a stable step: solver.dt_ms <=") != std::string::npos);
    CHECK(message.find("state 'm'") != std::string::npos);  // a gate pushed outside [0, 1], named
  }
  // The step the estimate calls stable really is.
  m["solver"]["dt_ms"] = 0.002;
  CHECK_NOTHROW(run(m));
}

TEST_CASE("very strong coupling with the implicit coupler: stable, and agrees with a 10x smaller step") {
  // D_m 10^5 nS between myocytes (explicit limit 2/lambda = 5e-4 ms); D_f 8 nS
  // on 6.3 pF fibroblasts in the pair.
  json strand = json::parse(R"({
    "fibrodem": 1, "name": "strong", "duration_ms": 350,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 8},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "coupling": {"D_m_nS": 100000, "scheme": "implicit"},
    "stimulus": [{"target": [0], "start_ms": 10, "duration_ms": 2, "amplitude_pA": 20000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [7], "variables": ["V"], "every_ms": 1}}
  })");
  const auto coarse = run(strand);
  strand["solver"]["dt_ms"] = 0.001;
  const auto fine = run(strand);
  REQUIRE(coarse.size() == 8);
  CHECK(std::abs(coarse[7].apd90_ms - fine[7].apd90_ms) < 1.0);
  CHECK(std::abs(coarse[7].activation_ms - fine[7].activation_ms) < 0.1);

  json pair = courtemanche_pair(4, "passive_fibroblast", 8);
  pair["coupling"]["scheme"] = "implicit";
  const auto p_coarse = run(pair);
  pair["solver"]["dt_ms"] = 0.001;
  const auto p_fine = run(pair);
  CHECK(std::abs(p_coarse[0].apd90_ms - p_fine[0].apd90_ms) < 1.0);
  CHECK(std::abs(p_coarse[1].apo_mV - p_fine[1].apo_mV) < 0.5);
}

namespace {
// Pulses of `duration_ms` into a passive fibroblast from rest, once a second:
// each must deliver its charge, a rise of exactly I R (1 - exp(-duration / RC)).
void check_pulses_deliver_charge(const json& solver, double duration_ms, double amplitude_pA, int count) {
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 1000.0 * count;
  m["stimulus"] = json::array({{{"target", "fibroblast"}, {"start_ms", 500.05}, {"duration_ms", duration_ms},
                                {"amplitude_pA", amplitude_pA}, {"period_ms", 1000}, {"count", count}}});
  m["solver"] = solver;
  m["output"]["traces"] = {{"cells", json::array()}};
  const auto beats = run(m);
  REQUIRE(beats.size() == static_cast<std::size_t>(count));
  const double rise = amplitude_pA * 10.7 * (1 - std::exp(-duration_ms / (10.7 * 6.3)));
  for (const auto& b : beats) {
    CAPTURE(b.beat);
    CHECK(b.apo_mV - b.rmp_mV == doctest::Approx(rise).epsilon(1e-3));
  }
}
}  // namespace

TEST_CASE("CVODE and adaptive never step over a pulse: each pulse between quiet stretches delivers its charge") {
  SUBCASE("CVODE, 100 pulses of 2 ms at 1 Hz, no step cap") {
    check_pulses_deliver_charge({{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-8}, {"max_step_ms", 1e6}}, 2, 10,
                                100);
  }
  SUBCASE("adaptive, 10 pulses of 0.1 ms at 1 Hz") {
    check_pulses_deliver_charge({{"method", "adaptive"}}, 0.1, 100, 10);
  }
}

TEST_CASE("100 beats at 1 Hz: ionic concentrations drift only as the model itself does (Rush-Larsen, adaptive)" * doctest::test_suite("slow")) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "long", "duration_ms": 100000,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "cellml"}},
    "stimulus": [{"target": "myocyte", "start_ms": 50, "duration_ms": 2, "amplitude_pA": 2000, "period_ms": 1000}],
    "output": {"traces": {"cells": [0], "variables": ["Na_i", "K_i", "Ca_i"], "every_ms": 1000, "from_ms": 999}}
  })");
  auto traces = [&](const json& solver) {
    m["solver"] = solver;
    Simulation sim(parse_scene(m));
    sim.run();
    return std::make_pair(sim.trace("Na_i", 0), sim.trace("K_i", 0));
  };
  const auto [na_cvode, k_cvode] = traces({{"method", "cvode"}, {"rtol", 1e-7}, {"atol", 1e-9}});
  REQUIRE(na_cvode.size() == 100);
  // The model itself loads Na_i over 100 beats (CellML start 11.17 mM; about +1 mM, see test_courtemanche).
  CHECK(na_cvode.back() - 11.17 > 0.5);
  // Rush-Larsen and the adaptive method follow the same drift: within 1 % of
  // CVODE at every beat (the drift itself, for Na_i).
  for (const json& solver : {json{{"method", "rush_larsen"}, {"dt_ms", 0.02}}, json{{"method", "adaptive"}}}) {
    CAPTURE(solver.dump());
    const auto [na, k_i] = traces(solver);
    REQUIRE(na.size() == 100);
    for (std::size_t k = 0; k < na_cvode.size(); ++k) {
      CAPTURE(k);
      CHECK(na[k] - 11.17 == doctest::Approx(na_cvode[k] - 11.17).epsilon(0.01));
      CHECK(k_i[k] == doctest::Approx(k_cvode[k]).epsilon(0.01));
    }
  }
}

namespace {
// A cell pair with D_f 0 and a strand of fibroblasts under `solver`.
void check_fibroblasts_rest(const json& solver) {
  // D_f = 0: the myocyte fires, the fibroblasts stay at their own rest.
  json pair_scene = courtemanche_pair(4, "maleckar_active2", 0.0);
  pair_scene["solver"] = solver;
  const auto pair = run(pair_scene);
  REQUIRE(pair.size() == 5);
  CHECK(pair[0].apo_mV > 0);
  for (int f = 1; f <= 4; ++f) {
    CHECK(pair[f].rmp_mV == doctest::Approx(-47.4).epsilon(0.01));  // maleckar_active2's rest
    CHECK_FALSE(fired(pair[f]));  // uncoupled: the myocyte's beat does not move them
  }
  // A strand of active fibroblasts, stimulated at one end.
  json strand = json::parse(R"({
    "fibrodem": 1, "name": "fibroblasts", "duration_ms": 300,
    "tissue": {"builder": "strand", "type": "fibroblast", "cells": 10},
    "cells": {"fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_f_nS": 2},
    "stimulus": [{"target": [0], "start_ms": 10, "duration_ms": 5, "amplitude_pA": 50}],
    "output": {"traces": {"cells": [0, 9], "variables": ["V"], "every_ms": 1}}
  })");
  strand["solver"] = solver;
  const auto fibroblasts = run(strand);
  REQUIRE(fibroblasts.size() == 10);
  CHECK(fired(fibroblasts[0]));  // the stimulus lifts it (50 pA for 5 ms into 6.3 pF: ~40 mV)
  for (const auto& b : fibroblasts) {
    CHECK(b.rmp_mV == doctest::Approx(-47.4).epsilon(0.01));
    if (fired(b)) CHECK(b.apo_mV < 0);  // fibroblasts are not excitable
  }
}
}  // namespace

TEST_CASE("isolated fibroblasts and fibroblast-only tissue: no crash, no NaN, sensible rest (Rush-Larsen, adaptive)") {
  for (const json& solver : {json{{"method", "rush_larsen"}, {"dt_ms", 0.01}}, json{{"method", "adaptive"}}}) {
    CAPTURE(solver.dump());
    check_fibroblasts_rest(solver);
  }
}

TEST_CASE("a concentration below zero is caught and named") {
  const auto dir = std::filesystem::path(FIBRODEM_BINARY_DIR);
  auto registry = std::make_shared<PluginRegistry>(
      std::vector<std::filesystem::path>{dir / "test_plugins", dir / "plugins"});
  json m = testing::passive_cell_manifest();
  m["cells"]["fibroblast"]["model"] = "drain";
  m["stimulus"] = json::array();
  // X_i = 1 mM drains at 0.01 mM/ms: zero at 100 ms.
  m["duration_ms"] = 200;
  Simulation sim(parse_scene(m), registry);
  CHECK_THROWS_WITH(sim.run(), doctest::Contains("state 'X_i'"));
  CHECK(sim.trace_times().back() < 101);
  CHECK(sim.trace_times().back() > 99);
}

TEST_CASE("F-M ratios up to 4 in-series: no crash, no NaN, resting potentials between the cells' own") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "fm4", "seed": 5, "duration_ms": 60,
    "tissue": {"builder": "in_series", "width_mm": 0.3, "height_mm": 1.0, "fm_ratio": 4.0},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 8},
    "stimulus": [{"target": "myocyte", "start_ms": 5, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  Simulation sim(parse_scene(m));
  sim.run();
  const json summary = sim.summary();
  CHECK(summary["fm_ratio"].get<double>() > 2.5);  // random placement: about 4
  for (const auto& b : sim.biomarkers()) {
    REQUIRE(std::isfinite(b.rmp_mV));
    REQUIRE(std::isfinite(b.apo_mV));
    // Between the fibroblast's own rest (-47.4 mV) and the myocyte's (-75.1 mV), with a margin.
    CHECK(b.rmp_mV > -80);
    CHECK(b.rmp_mV < -40);
  }
}
