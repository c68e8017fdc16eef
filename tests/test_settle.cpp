// cells.TYPE.settle (run/settle.hpp): each cell type's model alone before t = 0,
// at rest or paced, cached by everything that determines its end state.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// A passive fibroblast started at V = 0, settled at rest for `ms`.
json settled_passive(double ms, double R_GOhm) {
  json m = testing::passive_cell_manifest();
  m["stimulus"] = json::array();
  m["duration_ms"] = 2;
  m["cells"]["fibroblast"]["initial_state"] = {{"V", 0.0}};
  m["cells"]["fibroblast"]["parameters"] = {{"R_GOhm", R_GOhm}};
  m["cells"]["fibroblast"]["settle"] = {{"ms", ms}};
  return m;
}

std::string notes_of(const Simulation& sim) { return sim.summary()["notes"].dump(); }

}  // namespace

TEST_CASE("settle: a passive cell alone relaxes to the exact RC curve before t = 0, and is cached") {
  const auto cache = testing::scratch_dir("settle_cache");
  setenv("FIBRODEM_CACHE_DIR", cache.c_str(), 1);
  // Exact: V(t) = E + (V0 - E) exp(-t / RC), E = -49.6 mV, C = 6.3 pF, R = 1 GOhm:
  // RC = 6.3 ms; after 10 ms, V = -49.6 (1 - exp(-10/6.3)). CVODE at rtol 1e-6.
  const double exact = -49.6 * (1 - std::exp(-10.0 / 6.3));
  {
    Simulation sim(parse_scene(settled_passive(10, 1.0)));
    sim.run();
    CHECK(sim.trace("V", 0).front() == doctest::Approx(exact).epsilon(1e-5));
    CHECK(notes_of(sim).find("computed in") != std::string::npos);
  }
  {
    Simulation again(parse_scene(settled_passive(10, 1.0)));  // the same model, values and spec: from the cache
    again.run();
    CHECK(again.trace("V", 0).front() == doctest::Approx(exact).epsilon(1e-5));
    CHECK(notes_of(again).find("from the cache") != std::string::npos);
  }
  {
    Simulation other(parse_scene(settled_passive(10, 2.0)));  // another parameter: settled anew
    other.run();
    CHECK(notes_of(other).find("computed in") != std::string::npos);
    CHECK(other.trace("V", 0).front() == doctest::Approx(-49.6 * (1 - std::exp(-10.0 / 12.6))).epsilon(1e-5));
  }
  unsetenv("FIBRODEM_CACHE_DIR");
}

TEST_CASE("settle: a paced myocyte starts from its own diastole, so V hardly drifts at first") {
  const auto cache = testing::scratch_dir("settle_paced");
  setenv("FIBRODEM_CACHE_DIR", cache.c_str(), 1);
  auto run = [](bool settle) {
    // colman depolarised by raised extracellular K+ (off its default rest).
    json m = json::parse(R"({"fibrodem": 1, "name": "paced", "duration_ms": 20,
      "tissue": {"builder": "single_cell", "type": "myocyte"},
      "cells": {"myocyte": {"model": "colman", "parameters": {"K_o_mM": 7.5}}},
      "solver": {"method": "rush_larsen", "dt_ms": 0.01},
      "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 20}}})");
    if (settle) m["cells"]["myocyte"]["settle"] = {{"ms", 3000}, {"pacing", {{"period_ms", 1000}, {"amplitude_pA", 2000}}}};
    Simulation sim(parse_scene(m));
    sim.run();
    const auto& V = sim.trace("V", 0);
    return std::abs(V.back() - V.front());  // drift over the first 20 ms
  };
  const double unsettled = run(false), settled = run(true);
  CAPTURE(unsettled);
  CAPTURE(settled);
  CHECK(unsettled > 0.5);             // off its rest, the model drifts
  CHECK(settled < 0.1 * unsettled);  // settled, it stays
  unsetenv("FIBRODEM_CACHE_DIR");
}
