// solver.method "adaptive": error-controlled second-order
// Rush-Larsen with the coupling implicit. Exact solutions where there are
// some, CVODE at tight tolerance elsewhere, and the hard cases (stiff fibroblast coupling, stimulus edges).
#include <doctest/doctest.h>

#include <cmath>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

std::vector<BeatBiomarkers> run(const json& m) {
  Simulation sim(parse_scene(m));
  sim.run();
  return sim.biomarkers();
}

// A strand of courtemanche myocytes, D_m 1000 nS, stimulated at cell 0.
json courtemanche_strand(int cells, double duration_ms) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "strand", "tissue": {"builder": "strand", "type": "myocyte"},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0], "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  m["tissue"]["cells"] = cells;
  m["duration_ms"] = duration_ms;
  return m;
}

}  // namespace

TEST_CASE("adaptive on a passive cell: the exact RC charging curve, to the tolerance") {
  // passive_fibroblast: R = 10.7 GOhm, C = 6.3 pF, E = -49.6 mV (model defaults);
  // 1 pA from t = 0: V = E + I R (1 - exp(-t / RC)).
  json m = testing::passive_cell_manifest();
  m["solver"] = {{"method", "adaptive"}, {"rtol", 1e-5}, {"atol", 1e-5}};
  Simulation sim(parse_scene(m));
  sim.run();
  const auto& V = sim.trace("V", 0);
  const auto& t = sim.trace_times();
  REQUIRE(V.size() == 101);
  const double E = V[0], RC = 10.7 * 6.3;
  for (std::size_t k = 0; k < V.size(); ++k) {
    CAPTURE(t[k]);
    CHECK(V[k] == doctest::Approx(E + 10.7 * (1 - std::exp(-t[k] / RC))).epsilon(1e-5));
  }
}

TEST_CASE("adaptive and CVODE agree on the strand: activation within 0.1 ms, APD90 within 1 ms") {
  json strand = courtemanche_strand(20, 400);
  // Three cells paced: 4 nA into cell 0 alone leaves the strand at rest
  // (cell 0 reaches -63 mV), with nothing to compare.
  strand["stimulus"][0]["target"] = {0, 1, 2};
  json cvode = strand, adaptive = strand;
  cvode["solver"] = {{"method", "cvode"}, {"rtol", 1e-7}, {"atol", 1e-9}};
  adaptive["solver"] = {{"method", "adaptive"}};  // default tolerances
  const auto reference = run(cvode);
  const auto beats = run(adaptive);
  REQUIRE(reference.size() == 20);
  REQUIRE(beats.size() == 20);
  for (std::size_t c = 0; c < 20; ++c) {
    CAPTURE(c);
    REQUIRE(fired(reference[c]));
    REQUIRE(fired(beats[c]));
    CHECK(std::abs(beats[c].activation_ms - reference[c].activation_ms) < 0.1);
    CHECK(std::abs(beats[c].apd90_ms - reference[c].apd90_ms) < 1.0);
  }
}

TEST_CASE("adaptive with D_m 1e5 nS: the coupling never caps the step, and it agrees with CVODE") {
  // Explicit coupling would need dt < 5e-4 ms here (2/lambda).
  json strand = courtemanche_strand(8, 350);
  strand["coupling"]["D_m_nS"] = 100000;
  strand["stimulus"][0]["amplitude_pA"] = 20000;
  json cvode = strand;
  strand["solver"] = {{"method", "adaptive"}};
  strand["output"]["traces"]["variables"] = {"V", "dt_ms"};
  Simulation sim(parse_scene(strand));
  sim.run();
  cvode["solver"] = {{"method", "cvode"}, {"rtol", 1e-7}, {"atol", 1e-9}};
  const auto reference = run(cvode);
  const auto& beats = sim.biomarkers();
  REQUIRE(beats.size() == 8);
  REQUIRE(fired(reference[7]));
  CHECK(std::abs(beats[7].apd90_ms - reference[7].apd90_ms) < 1.0);
  CHECK(std::abs(beats[7].activation_ms - reference[7].activation_ms) < 0.1);
  // At rest, after the beat, it steps far beyond the explicit limit.
  const auto& dt = sim.trace("dt_ms", 0);
  CHECK(dt.back() > 0.1);
}

TEST_CASE("adaptive: 2 nA into a 6.3 pF fibroblast stops with a named blow-up, not NaN") {
  // 2000 pA / 6.3 pF drives V up at ~300 mV/ms: the solution itself leaves
  // the model's range [-190, 200] mV within the pulse.
  json m = json::parse(R"({
    "fibrodem": 1, "name": "f2na", "duration_ms": 50,
    "tissue": {"builder": "single_cell", "type": "fibroblast"},
    "cells": {"fibroblast": {"model": "maleckar_active2"}},
    "stimulus": [{"target": "fibroblast", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "adaptive"},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  Simulation sim(parse_scene(m));
  try {
    sim.run();
    FAIL("expected a blow-up");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.find("blow-up at t = 10.") != std::string::npos);
    CHECK(message.find("state 'V'") != std::string::npos);
  }
  // What was computed before stays: samples up to the blow-up.
  CHECK(sim.trace_times().back() == doctest::Approx(10));
}

TEST_CASE("adaptive: same numbers for 1, 2 and 3 threads" * doctest::test_suite("threads")) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "threads", "seed": 3, "duration_ms": 40,
    "tissue": {"builder": "in_series", "width_mm": 0.8, "height_mm": 2.5, "fm_ratio": 0.41},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 0.3},
    "stimulus": [{"target": {"type": "myocyte", "y_min_frac": 0.9}, "start_ms": 5, "duration_ms": 2,
                  "amplitude_pA": 2000}],
    "solver": {"method": "adaptive"},
    "output": {"traces": {"cells": [0, 100, 500], "variables": ["V", "dt_ms"], "every_ms": 0.5}}
  })");
  std::vector<std::vector<double>> first;
  for (int threads : {1, 2, 3}) {
    CAPTURE(threads);
    m["solver"]["threads"] = threads;
    Simulation sim(parse_scene(m));
    sim.run();
    std::vector<std::vector<double>> traces{sim.trace("V", 0), sim.trace("V", 100), sim.trace("V", 500),
                                            sim.trace("dt_ms", 0)};
    if (first.empty()) first = traces;
    else CHECK(traces == first);  // bit for bit
  }
}

TEST_CASE("solver.method auto (the default): CVODE for a cell pair, adaptive for tissue, and says why") {
  json pair = json::parse(R"({
    "fibrodem": 1, "name": "pair", "duration_ms": 50,
    "tissue": {"builder": "cell_pair", "fibroblasts": 2},
    "cells": {"myocyte": {"model": "courtemanche"}, "fibroblast": {"model": "passive_fibroblast"}},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  {
    Simulation sim(parse_scene(pair));  // no solver at all: auto, accuracy 0.5 ms
    sim.run();
    const json choice = sim.summary()["solver_choice"];
    CHECK(choice["method"] == "cvode");
    CHECK(choice["rtol"].get<double>() == doctest::Approx(0.5 / 500));
    CHECK(choice["why"].get<std::string>().find("3 cell(s)") != std::string::npos);
  }
  json strand = courtemanche_strand(40, 50);
  strand["solver"] = {{"method", "auto"}, {"accuracy", 0.1}};
  Simulation sim(parse_scene(strand));
  sim.run();
  const json summary = sim.summary();
  CHECK(summary["solver_choice"]["method"] == "adaptive");
  // The rung of 0.1 ms in integrate/method_choice.cpp (1e-3: 0.094 ms on the Fig. 3 tissue).
  CHECK(summary["solver_choice"]["rtol"].get<double>() == doctest::Approx(1e-3));
  CHECK(summary["integrator"].get<std::string>().find("adaptive") != std::string::npos);
  // A named method: no choice made, none reported.
  strand["solver"] = {{"method", "rush_larsen"}, {"dt_ms", 0.01}};
  Simulation named(parse_scene(strand));
  CHECK_FALSE(named.summary().contains("solver_choice"));
}

TEST_CASE("solver.method auto sets dt_ms, rtol and atol itself: giving them is an error naming the key") {
  json m = courtemanche_strand(4, 10);
  m["solver"] = {{"dt_ms", 0.01}};  // method unset: auto
  CHECK_THROWS_WITH(parse_scene(m), doctest::Contains("solver.dt_ms"));
  m["solver"] = {{"method", "auto"}, {"rtol", 1e-4}};
  CHECK_THROWS_WITH(parse_scene(m), doctest::Contains("solver.rtol"));
  m["solver"] = {{"method", "cvode"}, {"accuracy", 0.1}};
  CHECK_THROWS_WITH(parse_scene(m), doctest::Contains("solver.accuracy"));
  m["solver"] = {{"method", "adaptive"}, {"coupling_dt", 1}};
  CHECK_THROWS(parse_scene(m));
}

TEST_CASE("adaptive with DEM mechanics: the DEM keeps its own step, peak strain within 1 % of Rush-Larsen 0.01 ms") {
  // A small in-series tissue that contracts (colman + rice, Table 1 DEM).
  json m = json::parse(R"({
    "fibrodem": 1, "name": "em", "seed": 2, "duration_ms": 250,
    "effects": ["electrophysiology", "coupling", "mechanics"],
    "tissue": {"builder": "in_series", "width_mm": 0.3, "height_mm": 0.8, "fm_ratio": 0.41},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 0.3},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2,
                  "amplitude_pA": 2000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 0.5}}
  })");
  auto peak_strain = [&](const json& solver) {
    m["solver"] = solver;
    Simulation sim(parse_scene(m));
    sim.run();
    return sim.summary()["peak_strain"];
  };
  const json fixed = peak_strain({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
  const json adaptive = peak_strain({{"method", "adaptive"}});
  // Along the fibre (yy) the tissue shortens; across (xx) it barely moves
  // here: that component is held to 1 % of the fibre's.
  const double yy = fixed["yy"].get<double>();
  REQUIRE(std::abs(yy) > 0.01);  // it did contract
  CHECK(adaptive["yy"].get<double>() == doctest::Approx(yy).epsilon(0.01));
  CHECK(std::abs(adaptive["xx"].get<double>() - fixed["xx"].get<double>()) < 0.01 * std::abs(yy));
}
