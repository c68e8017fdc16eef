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

namespace {

// One colman myocyte coupled to four active fibroblasts (Maleckar 2009), no
// stimulus: the fibroblasts start at their isolated rest, about -47 mV,
// which the myocyte's coupling pulls down.
json coupled_pair_at_rest(double duration_ms) {
  return json::parse(R"({"fibrodem": 1, "name": "pair_rest", "duration_ms": )" + std::to_string(duration_ms) + R"(,
    "tissue": {"builder": "cell_pair", "fibroblasts": 4},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"law": "gap_junction", "D_m_nS": 1000, "D_f_nS": 8},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 1], "variables": ["V"], "every_ms": 1}}})");
}

}  // namespace

TEST_CASE("settle (the tissue): t = 0 is where the coupled tissue at rest would be after that long") {
  // The reference is the same tissue run from its unsettled start for 500 ms:
  // the settle is that run moved before t = 0 (the same fixed steps, no
  // stimulus), so the fibroblast's V agrees to round-off.
  Simulation unsettled(parse_scene(coupled_pair_at_rest(500)));
  unsettled.run();
  const auto& V_free = unsettled.trace("V", 1);
  json m = coupled_pair_at_rest(20);
  m["settle"] = {{"ms", 500}};
  Simulation settled(parse_scene(m));
  settled.run();
  const auto& V_settled = settled.trace("V", 1);
  CHECK(V_settled.front() == doctest::Approx(V_free.back()).epsilon(1e-9));
  // The transient the settle removes: over the unsettled run's first 20 ms
  // the fibroblast moves by several mV; settled, it hardly moves.
  const double drift_unsettled = std::abs(V_free[20] - V_free.front());
  const double drift_settled = std::abs(V_settled.back() - V_settled.front());
  CAPTURE(drift_unsettled);
  CAPTURE(drift_settled);
  CHECK(drift_unsettled > 1.0);
  CHECK(drift_settled < 0.05 * drift_unsettled);
  CHECK(notes_of(settled).find("settle: the coupled tissue at rest for 500 ms") != std::string::npos);
}

TEST_CASE("settle (the tissue): a negative length is refused, naming settle.ms") {
  json m = coupled_pair_at_rest(20);
  m["settle"] = {{"ms", -1}};
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("settle.ms"), ManifestError);
  m["settle"] = {{"ms", 10}, {"pacing", 1}};
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("settle.pacing"), ManifestError);
}
