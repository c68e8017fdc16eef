// mechano_electric_feedback.stretch "tissue": the stretch-activated current
// reads each cell's fibre stretch in the deforming DEM tissue
// (core/run/mechanics_coupling.cpp), so that contracting cells stretch and
// depolarise resting ones. Known answers: electrically uncoupled cells, so
// that an unstimulated cell's V moves only through that current; the
// sarcomere's stretch (an unloaded cell only shortens) and a conductance of 0
// leave V bit for bit as without feedback; the tissue's stretch depolarises
// the resting cells beside the contracting ones (E_SAC 0 mV above rest); the
// same bits on one thread and two; bad keys and the split run are refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "run/simulation.hpp"
#include "scene/scene.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// A sheet whose lower half is stimulated and, uncoupled, contracts alone.
json half_contracting_sheet() {
  return json::parse(R"({
    "fibrodem": 1, "name": "tissue_stretch", "duration_ms": 120, "seed": 1,
    "effects": ["electrophysiology", "mechanics", "mechano_electric_feedback"],
    "mechano_electric_feedback": {"stretch": "tissue"},
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.3, "length_mm": 0.75},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}},
    "stimulus": [{"target": {"y_max_frac": 0.5, "type": "myocyte"}, "start_ms": 1, "duration_ms": 2, "amplitude_pA": 4000}],
    "mechanics": {"skip_at_rest": false},
    "solver": {"method": "rush_larsen", "dt_ms": 0.02}
  })");
}

// The unstimulated cells within 0.2 mm above the stimulated half, traced.
std::vector<int> cells_above_the_border(json& m) {
  Simulation probe(parse_scene(m));
  const Tissue& t = probe.tissue();
  const double border_um = 375;
  std::vector<int> cells;
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.y_um[c] > border_um + 70 && t.y_um[c] < border_um + 200) cells.push_back(static_cast<int>(c));
  m["output"] = {{"traces", {{"cells", cells}, {"variables", {"V"}}, {"every_ms", 1}}}};
  return cells;
}

std::vector<std::vector<double>> V_of(const json& m, const std::vector<int>& cells) {
  Simulation sim(parse_scene(m));
  sim.run();
  REQUIRE(sim.summary()["status"] == "completed");
  std::vector<std::vector<double>> V;
  for (int c : cells) V.push_back(sim.trace("V", c));
  return V;
}

}  // namespace

TEST_CASE("tissue stretch: contracting cells depolarise the resting cells they stretch, the sarcomere's do not") {
  json m = half_contracting_sheet();
  const std::vector<int> cells = cells_above_the_border(m);
  REQUIRE(cells.size() >= 10);
  json ep = m;
  ep["effects"] = {"electrophysiology", "mechanics"};
  const auto none = V_of(ep, cells);
  // The sarcomere's stretch: an unloaded cell only shortens (lambda <= 1), so
  // no current flows, and V is that of the run without feedback.
  json sarcomere = m;
  sarcomere["mechano_electric_feedback"]["stretch"] = "sarcomere";
  CHECK(V_of(sarcomere, cells) == none);
  // The tissue's stretch with no conductance: nothing else changes.
  json closed = m;
  closed["mechano_electric_feedback"]["G_SAC_nS"] = 0;
  CHECK(V_of(closed, cells) == none);
  // The tissue's stretch: the resting cells above the border are pulled along
  // the fibres by the contracting half, and I_SAC (E 0 mV, above their rest
  // near -78 mV) depolarises them; it never hyperpolarises.
  const auto pulled = V_of(m, cells);
  double rise_mV = 0, fall_mV = 0;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (std::size_t k = 0; k < none[i].size(); ++k) {
      rise_mV = std::max(rise_mV, pulled[i][k] - none[i][k]);
      fall_mV = std::max(fall_mV, none[i][k] - pulled[i][k]);
    }
  MESSAGE("largest depolarisation by the tissue's stretch: ", rise_mV, " mV");
  CHECK(rise_mV > 0.05);
  CHECK(fall_mV < 1e-9);
  // None of them is excited: their V stays below -60 mV.
  for (const auto& v : pulled) CHECK(*std::max_element(v.begin(), v.end()) < -60);
}

TEST_CASE("tissue stretch: the same bits on one thread and on two" * doctest::test_suite("threads")) {
  json m = half_contracting_sheet();
  m["duration_ms"] = 60;
  const std::vector<int> cells = cells_above_the_border(m);
  m["solver"]["threads"] = 1;
  const auto one = V_of(m, cells);
  m["solver"]["threads"] = 2;
  CHECK(V_of(m, cells) == one);
}

TEST_CASE("tissue stretch: it builds mechanics, takes a type without a myofilament, and bad values are named") {
  json m = half_contracting_sheet();
  m["effects"] = {"electrophysiology", "mechano_electric_feedback"};
  {
    Simulation sim(parse_scene(m));
    CHECK(sim.processes().has("mechanics"));
  }
  m["mechano_electric_feedback"]["stretch"] = "sarcomeres";
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("mechano_electric_feedback.stretch"), ManifestError);
  // A fibroblast has no myofilament model but is stretched by the tissue.
  m = half_contracting_sheet();
  m["tissue"]["fibrosis"] = {{"density", 0.2}, {"pattern", "diffuse"}, {"as", "fibroblasts"}};
  m["cells"]["fibroblast"] = {{"model", "maleckar_active2"}};
  m["mechano_electric_feedback"]["cell_types"] = {"myocyte", "fibroblast"};
  m["duration_ms"] = 5;
  Simulation sim(parse_scene(m));
  sim.run();
  CHECK(sim.summary()["status"] == "completed");
}
