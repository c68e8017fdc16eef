// Whether a cell fired in a beat (measure/biomarkers.hpp): one definition,
// and every output that follows it. Known answers: a synthetic potential on
// either side of the 20 mV rise; a strand blocked by a segment of passive
// fibroblasts (the myocytes past it cannot fire); a sheet whose collagen cuts
// cells off from the stimulus (the cell graph says which: no current reaches
// them); a lone passive fibroblast; a fibroblast the myocyte's wave drives.
#include <doctest/doctest.h>

#include <cmath>
#include <algorithm>
#include <set>

#include "measure/biomarkers.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Rest at -80 mV, then from t = 10 ms a half-cosine rise of `rise_mV` over
// 1 ms and a linear fall back over 200 ms.
double bump(double t, double rise_mV) {
  if (t <= 10) return -80;
  if (t <= 11) return -80 + 0.5 * rise_mV * (1 - std::cos(kPi * (t - 10)));
  if (t <= 211) return -80 + rise_mV * (1 - (t - 11) / 200);
  return -80;
}

json run_scene(json m, const std::filesystem::path& dir) {
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  return sim.summary();
}

// biomarkers.csv's rows by cell (one beat in these scenes).
std::map<int, std::vector<std::string>> rows_by_cell(const std::filesystem::path& file) {
  std::map<int, std::vector<std::string>> rows;
  const auto table = testing::csv_rows(file);
  for (std::size_t k = 1; k < table.size(); ++k) rows[std::stoi(table[k][0])] = table[k];
  return rows;
}

// A strand of myocytes along y (a one-column fibrotic sheet, 40 cells of
// 125 um) whose middle fifth, cells 16-23, holds passive fibroblasts; paced
// at its first cells.
json blocked_strand() {
  return json::parse(R"({
    "fibrodem": 1, "name": "blocked_strand", "seed": 1, "duration_ms": 60,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.025, "length_mm": 5,
               "fibrosis": {"pattern": "compact", "density": 0.2, "aspect": 40, "as": "fibroblasts"}},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013"},
              "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 2},
    "stimulus": [{"target": {"y_min_frac": 0, "y_max_frac": 0.06, "type": "myocyte"},
                  "start_ms": 5, "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 0.5}, "maps": true, "report": false}
  })");
}

}  // namespace

TEST_CASE("a cell fires when it rises 20 mV (myocyte) or 1 mV (fibroblast) above its onset V, else no activation") {
  // Myocytes: an action potential, rises of 25 and 15 mV, rest; fibroblasts:
  // rises of 4 and 0.5 mV (driven, and a drift), rest.
  const std::vector<CellType> types = {CellType::myocyte, CellType::myocyte, CellType::myocyte, CellType::myocyte,
                                       CellType::fibroblast, CellType::fibroblast, CellType::fibroblast};
  const double rises[] = {100, 25, 15, 0, 4, 0.5, 0};
  const bool fires[] = {true, true, false, false, true, false, false};
  const std::size_t n = types.size();
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker(types, {5.0}, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  auto V_at = [&](double t) {
    std::vector<double> V(n);
    for (std::size_t c = 0; c < n; ++c) V[c] = bump(t, rises[c]);
    return V;
  };
  std::vector<double> V = V_at(0);
  tracker.start(0, V.data());
  const double h = 0.01;
  for (long k = 0; k < 30000; ++k) {
    V = V_at(static_cast<double>(k + 1) * h);
    tracker.step(static_cast<double>(k) * h, static_cast<double>(k + 1) * h, V.data(), nullptr);
  }
  tracker.finish();
  REQUIRE(beats.size() == n);
  for (const auto& b : beats) {
    CAPTURE(b.cell);
    const auto c = static_cast<std::size_t>(b.cell);
    CHECK(fired(b) == fires[c]);
    CHECK(b.rmp_mV == -80);  // the onset V is measured either way
    if (fires[c]) {
      // The steepest point of the half-cosine, 10.5 ms, to within a step.
      CHECK(b.activation_ms == doctest::Approx(10.5).epsilon(h / 10.5));
      CHECK(b.apo_mV == doctest::Approx(-80 + rises[c]));
      // APD90 ends at -80 + 0.1 rise: 11 + 0.9 * 200 ms.
      CHECK(b.apd90_ms == doctest::Approx(191 - b.activation_ms).epsilon(1e-6));
    } else {
      CHECK(std::isnan(b.activation_ms));
      CHECK(std::isnan(b.apo_mV));
      CHECK(std::isnan(b.apd90_ms));
      CHECK(std::isnan(b.apd50_ms));
      CHECK(std::isnan(b.dvdt_max_mV_per_ms));
    }
  }
}

TEST_CASE("a strand blocked by passive fibroblasts: the myocytes past the block have no activation anywhere") {
  const auto dir = testing::scratch_dir("firing_blocked_strand");
  const json summary = run_scene(blocked_strand(), dir);
  REQUIRE(summary["status"] == "completed");
  REQUIRE(summary["cells"]["myocyte"] == 32);
  REQUIRE(summary["cells"]["fibroblast"] == 8);
  const auto rows = rows_by_cell(dir / "biomarkers.csv");
  REQUIRE(rows.size() == 40);
  // The cells are numbered along the strand: myocytes 0-15, fibroblasts
  // 16-23, myocytes 24-39 (the block is at cell 16).
  int fibroblasts_fired = 0;
  for (const auto& [cell, row] : rows) {
    const int cell_number = cell;  // (a structured binding: clang 14's lambdas cannot capture it)
    CAPTURE(cell_number);
    REQUIRE(row.size() == 9);
    const bool before_block = cell < 16, fibroblast = cell >= 16 && cell < 24;
    CHECK(row[1] == (fibroblast ? "fibroblast" : "myocyte"));
    CHECK(!row[4].empty());  // the RMP is measured in every beat
    if (before_block) {
      CHECK(!row[3].empty());
      CHECK(std::stod(row[5]) > 0);  // an overshoot: a real action potential
    } else if (!fibroblast) {
      // Past the block: every measured field empty, none "0" or "nan".
      for (int k : {3, 5, 6, 7, 8}) CHECK(row[static_cast<std::size_t>(k)].empty());
    } else {
      fibroblasts_fired += !row[3].empty();
    }
  }
  // The wave depolarises the first fibroblasts of the segment, not the far ones.
  CHECK(fibroblasts_fired >= 1);
  CHECK(fibroblasts_fired < 8);
  CHECK(rows.at(16)[3].size() > 0);
  CHECK(rows.at(23)[3].empty());
  const json& myocytes = summary["mean_biomarkers"]["myocyte"];
  CHECK(myocytes["beats_measured"] == 16);
  CHECK(myocytes["beats_not_fired"] == 16);
  CHECK(summary["mean_biomarkers"]["fibroblast"]["beats_not_fired"] == 8 - fibroblasts_fired);
  // The mean APO is over the 16 action potentials only: above 0 mV (the cells
  // at rest past the block would pull a mean over 32 cells below -30 mV).
  CHECK(myocytes["apo_mV"].get<double>() > 0);
  // The maps: NaN past the block, a number before it.
  const std::string vtk = testing::read_file(dir / "maps.vtk");
  CHECK(vtk.find("nan") != std::string::npos);
}

TEST_CASE("collagen that cuts cells off the stimulus: they never fire, count as unreached, and are grey in the map") {
  // A patchy collagen sheet as the caf_sheet example, cropped to 3 x 3 mm.
  json m = json::parse(testing::read_file(std::filesystem::path(FIBRODEM_SOURCE_DIR) / "examples" / "arrhythmia" /
                                          "caf_sheet.json"));
  m["tissue"]["width_mm"] = 3;
  m["tissue"]["length_mm"] = 3;
  m["tissue"]["fibrosis"]["density"] = 0.3;
  m["duration_ms"] = 40;
  // Paced at the cells whose centre lies within 0.4 mm of the lower edge.
  m["stimulus"][0]["target"] = {{"x_min_mm", -1}, {"x_max_mm", 4}, {"y_min_mm", -1}, {"y_max_mm", 0.4}};
  m["output"] = {{"maps", true}, {"report", false}, {"reentry", {{"every_ms", 1}}}};
  const auto dir = testing::scratch_dir("firing_cut_off");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  const json summary = sim.summary();
  REQUIRE(summary["status"] == "completed");

  // The cells a current can reach: those joined to a stimulated cell through
  // the cell graph (gap junctions). No path, no current: they cannot fire.
  const Tissue& tissue = sim.tissue();
  const std::size_t n = tissue.cell_count();
  const CellComponents parts = cell_graph_components(tissue);
  std::set<int> stimulated_parts;
  for (std::size_t c = 0; c < n; ++c)
    if (tissue.y_um[c] <= 400) stimulated_parts.insert(parts.component[c]);
  REQUIRE(!stimulated_parts.empty());
  std::vector<char> joined(n, 0);
  for (std::size_t c = 0; c < n; ++c) joined[c] = stimulated_parts.count(parts.component[c]) > 0;
  const auto cut_off = static_cast<std::size_t>(std::count(joined.begin(), joined.end(), 0));
  REQUIRE(cut_off > 0);  // the sheet must have islands for this test to say anything

  const auto rows = rows_by_cell(dir / "biomarkers.csv");
  REQUIRE(rows.size() == n);
  std::size_t not_fired = 0, joined_fired = 0;
  for (const auto& [cell, row] : rows) {
    not_fired += row[3].empty();
    joined_fired += joined[static_cast<std::size_t>(cell)] && !row[3].empty();
    if (joined[static_cast<std::size_t>(cell)]) continue;
    const int cell_number = cell;  // (a structured binding: clang 14's lambdas cannot capture it)
    CAPTURE(cell_number);
    CHECK(row[3].empty());  // no activation time
    CHECK(row[5].empty());  // no APO
    CHECK(row[7].empty());  // no max dV/dt
  }
  // The wave crosses the rest of the sheet: the cells joined to the stimulus
  // fire, but for a few behind a narrow isthmus (source-sink mismatch).
  CHECK(joined_fired > 0.9 * static_cast<double>(n - cut_off));
  CHECK(not_fired >= cut_off);
  CHECK(summary["mean_biomarkers"]["myocyte"]["beats_not_fired"] == not_fired);
  // The unreached fraction of the re-entry measures counts the same cells.
  const json& unreached = summary["reentry"]["unreached_fraction_per_beat"];
  REQUIRE(unreached.size() == 1);
  CHECK(unreached[0]["fraction"].get<double>() == doctest::Approx(static_cast<double>(not_fired) / n));
}

TEST_CASE("a lone passive fibroblast never fires, and one a myocyte's action potential drives does") {
  {
    json m = testing::passive_cell_manifest();
    m["stimulus"] = json::array();
    m["duration_ms"] = 50;
    const auto dir = testing::scratch_dir("firing_lone_fibroblast");
    const json summary = run_scene(m, dir);
    const auto rows = rows_by_cell(dir / "biomarkers.csv");
    REQUIRE(rows.size() == 1);
    CHECK(rows.at(0)[3].empty());
    CHECK(summary["mean_biomarkers"]["fibroblast"]["beats_measured"] == 0);
    CHECK(summary["mean_biomarkers"]["fibroblast"]["beats_not_fired"] == 1);
  }
  // The paper's cell pair: the fibroblasts follow the myocyte's upstroke
  // through their gap junctions, so they fire in this sense, just after it.
  json m = json::parse(testing::read_file(std::filesystem::path(FIBRODEM_SOURCE_DIR) / "examples" /
                                          "cell_pair_passive.json"));
  m["duration_ms"] = 400;
  m["output"] = {{"report", false}};
  const auto dir = testing::scratch_dir("firing_cell_pair");
  run_scene(m, dir);
  const auto table = testing::csv_rows(dir / "biomarkers.csv");
  double myocyte_activation = NAN;
  std::vector<double> fibroblast_activations;
  for (std::size_t k = 1; k < table.size(); ++k) {
    if (table[k][2] != "0") continue;  // the first beat
    REQUIRE(!table[k][3].empty());
    (table[k][1] == "myocyte" ? myocyte_activation : fibroblast_activations.emplace_back()) = std::stod(table[k][3]);
  }
  REQUIRE(!fibroblast_activations.empty());
  for (double t : fibroblast_activations) CHECK(std::abs(t - myocyte_activation) < 2.0);
}
