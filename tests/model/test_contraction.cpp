// Excitation-contraction in a whole run: a myofilament model rides on the
// myocyte's Ca_i; with one-way coupling it cannot change V (bit for bit), with
// calcium feedback it does; only what the scene calls for is built.
#include <doctest/doctest.h>

#include <cmath>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
json em_cell(const std::string& effects_json) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "em", "duration_ms": 1000,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}},
    "stimulus": [{"target": "myocyte", "start_ms": 50, "duration_ms": 2, "amplitude_pA": 2000, "period_ms": 1000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0], "variables": ["V", "Ca_i"], "every_ms": 0.5}}
  })");
  m["effects"] = json::parse(effects_json);
  return m;
}

struct Run {
  std::vector<double> V, Ca_i, SL;
  ProcessPlan plan;
};

Run run(const json& m, bool with_sl = false) {
  json manifest = m;
  if (with_sl) manifest["output"]["traces"]["variables"].push_back("sarcomere_length");
  Simulation sim(parse_scene(manifest));
  sim.run();
  Run r{sim.trace("V", 0), sim.trace("Ca_i", 0), {}, sim.processes()};
  if (with_sl) r.SL = sim.trace("sarcomere_length", 0);
  return r;
}
}  // namespace

TEST_CASE("contraction with one-way coupling leaves the membrane potential bit for bit unchanged") {
  const Run ep = run(em_cell(R"(["electrophysiology"])"));
  CHECK_FALSE(ep.plan.has("contraction"));
  const Run em = run(em_cell(R"(["electrophysiology", "contraction"])"), true);
  CHECK(em.plan.has("contraction"));
  REQUIRE(ep.V.size() == em.V.size());
  CHECK(ep.V == em.V);        // exactly, not approximately
  CHECK(ep.Ca_i == em.Ca_i);
  // And the cell did contract.
  const double sl_rest = em.SL.front();
  const double sl_min = *std::min_element(em.SL.begin(), em.SL.end());
  CHECK(sl_min < 0.97 * sl_rest);
}

TEST_CASE("calcium feedback changes the calcium transient and the action potential") {
  json m = em_cell(R"(["electrophysiology", "contraction"])");
  const Run one_way = run(m);
  m["cells"]["myocyte"]["calcium_feedback"] = true;
  const Run feedback = run(m);
  REQUIRE(one_way.V.size() == feedback.V.size());
  double dV = 0, dCa = 0;
  for (std::size_t k = 0; k < one_way.V.size(); ++k) {
    dV = std::max(dV, std::abs(one_way.V[k] - feedback.V[k]));
    dCa = std::max(dCa, std::abs(one_way.Ca_i[k] - feedback.Ca_i[k]));
  }
  CAPTURE(dV);
  CAPTURE(dCa);
  CHECK(dCa > 1e-6);  // mM: troponin binding buffers the transient visibly (> 1 nM)
  CHECK(dV > 1e-3);
}

TEST_CASE("tracing a myofilament variable calls for contraction, without it rice is never loaded") {
  json m = em_cell("[]");
  m.erase("effects");
  m["duration_ms"] = 100;
  Simulation ep_only(parse_scene(m));
  CHECK_FALSE(ep_only.processes().has("contraction"));
  bool noted = false;
  for (const auto& n : ep_only.processes().notes) noted = noted || n.find("not loaded") != std::string::npos;
  CHECK(noted);
  m["output"]["traces"]["variables"].push_back("sarcomere_length");
  Simulation em(parse_scene(m));
  CHECK(em.processes().has("contraction"));
}

TEST_CASE("contraction needs a myofilament model, feedback needs a host that takes it") {
  json m = em_cell(R"(["electrophysiology", "contraction"])");
  m["cells"]["myocyte"].erase("myofilament");
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(m)), doctest::Contains("myofilament"), ManifestError);
  m = em_cell(R"(["electrophysiology", "contraction"])");
  m["cells"]["myocyte"]["myofilament"] = "passive_fibroblast";
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(m)), doctest::Contains("cells.myocyte.myofilament.model"), ManifestError);
}

TEST_CASE("mechano-electric feedback: no stretch-activated current while the cell is not stretched") {
  // An unloaded cell only shortens (lambda = SL/SL_rest <= 1), so I_SAC stays 0
  // and V is that of the EP-only scene; MEF alone builds contraction for lambda.
  json m = em_cell(R"(["electrophysiology", "mechano_electric_feedback"])");
  m["duration_ms"] = 200;
  json ep = em_cell(R"(["electrophysiology"])");
  ep["duration_ms"] = 200;
  const Run mef = run(m);
  CHECK(mef.plan.has("contraction"));
  CHECK(mef.V == run(ep).V);
}

TEST_CASE("mechanics: the tissue contracts, strain is traced, and V is bit for bit that of the scene without it") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "em_tissue", "seed": 3, "duration_ms": 250,
    "tissue": {"builder": "in_series", "width_mm": 0.25, "height_mm": 0.8, "fm_ratio": 0.2},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 0.3},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 5], "variables": ["V"], "every_ms": 1}}
  })");
  // (Every myocyte stimulated: a tissue this small cannot source a travelling wave
  // from its top 10 %; the point here is contraction, not conduction.)
  m["effects"] = {"electrophysiology", "coupling", "contraction"};
  Simulation without(parse_scene(m));
  without.run();
  m["effects"] = {"electrophysiology", "coupling", "mechanics"};
  Simulation with(parse_scene(m));
  with.run();
  CHECK(with.processes().has("contraction"));
  CHECK(with.trace("V", 0) == without.trace("V", 0));
  CHECK(with.trace("V", 5) == without.trace("V", 5));
  // Fibres run along y: the tissue shortens along them and widens across, by
  // about the cells' 10 % shortening (the seed's peak tissue strain ~0.098).
  const json peak = with.summary()["peak_strain"];
  CAPTURE(peak.dump());
  CHECK(peak["yy"].get<double>() < -0.05);
  CHECK(peak["yy"].get<double>() > -0.15);
  CHECK(peak["xx"].get<double>() > 0.03);
  const auto names = with.trace_column_names();
  CHECK(std::find(names.begin(), names.end(), "eps_yy") != names.end());
  CHECK(without.summary()["peak_strain"].is_null());
}

TEST_CASE("mechanics: a lone myocyte has no contacts, yet DEM steps and its particles close up") {
  // No contact, no stiffness limit: the step is capped at 1 ms (before the
  // cap, the step was infinite and DEM never moved: strain 0).
  json m = json::parse(R"({
    "fibrodem": 1, "name": "lone_em", "duration_ms": 300,
    "effects": ["electrophysiology", "mechanics"],
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  Simulation sim(parse_scene(m));
  sim.run();
  const json s = sim.summary();
  CHECK(s["mechanics_step_ms"].get<double>() == doctest::Approx(1.0));
  // Its 7 particles close up along the fibre (y) as it shortens by ~10 %.
  CHECK(s["peak_strain"]["yy"].get<double>() < -0.02);
}

TEST_CASE("mechano-electric feedback: cell_types switches the stretch-activated current per cell type") {
  // Rice's series elastic afterload pulls SL towards SLset (KSE (SLset - SL)):
  // with SLset 2.0 um above the initial SL of 1.9 um the unstimulated cell is
  // stretched (lambda up to 2.0 / 1.9 = 1.05), so the default current (5 nS at
  // lambda_max 1.1, E 0 mV, at rest ~-75 mV) depolarises it.
  json m = em_cell(R"(["electrophysiology", "mechano_electric_feedback"])");
  m["duration_ms"] = 40;
  m["stimulus"] = json::array();
  m["cells"]["myocyte"]["myofilament"] = {{"model", "rice"}, {"parameters", {{"SLset", 2.0}}}};
  json ep = m;
  ep["effects"] = {"electrophysiology"};
  const Run none = run(ep), by_default = run(m, true);
  CHECK(by_default.SL.back() > 1.01 * by_default.SL.front());  // stretched
  CHECK(by_default.V.back() > none.V.back() + 0.01);          // depolarised by I_SAC
  m["mechano_electric_feedback"] = {{"cell_types", {"myocyte"}}};
  CHECK(run(m).V == by_default.V);  // listed: as the default (the myocytes have the myofilament)
  m["mechano_electric_feedback"] = {{"cell_types", json::array()}};
  CHECK(run(m).V == none.V);  // off for every type: V of the scene without feedback, bit for bit
  // A type listed without a myofilament model has no stretch: refused, naming the key.
  m["mechano_electric_feedback"] = {{"cell_types", {"myocyte", "fibroblast"}}};
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(m)),
                       doctest::Contains("mechano_electric_feedback.cell_types: the stretch-activated current of "
                                         "fibroblast cells needs their stretch"),
                       ManifestError);
  m["mechano_electric_feedback"] = {{"cell_types", {"myocytes"}}};
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("mechano_electric_feedback.cell_types"), ManifestError);
}
