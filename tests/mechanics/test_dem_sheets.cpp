// `fibrotic_sheet` as a DEM body (core/tissue/builders/fibrotic_sheet.cpp):
// its bonds give exactly the brick wall's cell graph for every pattern and
// `as`; each pattern and collagen mode builds a body that stays at rest;
// collagen particles and bonds through collagen take the collagen's
// stiffness, while the other contacts keep theirs; a collagen stiffness of 0
// and a DEM too large for the memory are refused before any step; the
// schemes' acceptance bounds (tests/support/dem_twitch.hpp) on a sheet; an
// electromechanical sheet gives the same bits on one thread and on two.
#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "mechanics/dem_solver.hpp"
#include "run/resource_estimate.hpp"
#include "support/dem_twitch.hpp"
#include "support/dem_probe.hpp"
#include "support/scenes.hpp"
#include "tissue/builders/column_tissue.hpp"

using namespace fibrodem;
using namespace fibrodem::test;

namespace {

json sheet(double width_mm, double length_mm, const json& fibrosis = json()) {
  json t = {{"builder", "fibrotic_sheet"}, {"width_mm", width_mm}, {"length_mm", length_mm}};
  if (!fibrosis.is_null()) t["fibrosis"] = fibrosis;
  return t;
}

const std::vector<std::string> kPatterns = {"diffuse", "patchy", "interstitial", "compact"};

json fibrosis(const std::string& pattern, const std::string& as, const std::string& collagen = "voids") {
  json f = {{"density", 0.25}, {"pattern", pattern}, {"as", as}};
  if (as == "collagen") f["collagen"] = collagen;
  return f;
}

// Each pattern with fibroblasts, and with collagen as voids and as particles.
template <class Body>
void for_each_fibrosis(Body body) {
  for (const std::string& pattern : kPatterns)
    for (const std::string as : {"fibroblasts", "collagen"})
      for (const std::string collagen : {"voids", "particles"}) {
        if (as == "fibroblasts" && collagen == "particles") continue;
        CAPTURE(pattern);
        CAPTURE(as);
        CAPTURE(collagen);
        body(pattern, as, collagen);
      }
}

// The brick wall's cell graph from the cells' centres alone (docs/topics/fibrosis.md,
// "Layout"): a cell is coupled to the next one in its column (125 um up) and
// to the cells of the neighbouring columns (23.57 um across) whose centres lie
// half a cell (62.5 um) above or below it, except across a septum: where, in
// `septum_cells` (the interstitial lines), either cell is in a line.
std::set<std::pair<int, int>> brick_graph(const Tissue& t, const std::vector<char>& septum_cells) {
  std::set<std::pair<int, int>> edges;
  const double px = kColumnPitch_um, py = kMyocyteLength_um;
  for (std::size_t i = 0; i < t.cell_count(); ++i)
    for (std::size_t j = i + 1; j < t.cell_count(); ++j) {
      const double dx = std::abs(t.x_um[i] - t.x_um[j]), dy = std::abs(t.y_um[i] - t.y_um[j]);
      const bool along = dx < 1e-6 && std::abs(dy - py) < 1e-6;
      const bool beside = std::abs(dx - px) < 1e-6 && std::abs(dy - py / 2) < 1e-6;
      const bool cut = beside && !septum_cells.empty() && (septum_cells[i] || septum_cells[j]);
      if ((along || beside) && !cut) edges.insert({static_cast<int>(i), static_cast<int>(j)});
    }
  return edges;
}

}  // namespace

TEST_CASE("dem sheets: the bonds give the brick wall's cell graph, for every pattern and as") {
  // 0.6 x 1.5 mm: 25 columns x 11 rows; density 0.25. The expected graph is
  // built from the cells' centres, independently of the bonds.
  for_each_fibrosis([](const std::string& pattern, const std::string& as, const std::string& collagen) {
    const Tissue t = testing::build_tissue(sheet(0.6, 1.5, fibrosis(pattern, as, collagen)), 5);
    std::vector<char> septum;
    if (as == "collagen" && pattern == "interstitial") {
      const Tissue lines = testing::build_tissue(sheet(0.6, 1.5, fibrosis(pattern, "fibroblasts")), 5);
      for (CellType type : lines.type) septum.push_back(type == CellType::fibroblast);
    }
    const auto expected = brick_graph(t, septum);
    CHECK(std::set<std::pair<int, int>>(t.cell_edges.begin(), t.cell_edges.end()) == expected);
    CHECK(t.cell_edges.size() == expected.size());
    CHECK_FALSE(t.bonds.empty());
    // Every bond joins touching particles (overlap at most the in-series 1.43 um).
    const std::size_t np = t.particles.size();
    auto at = [&](int k) -> const Particle& {
      return static_cast<std::size_t>(k) < np ? t.particles[k] : t.collagen[k - np];
    };
    for (const auto* set : {&t.bonds, &t.collagen_bonds})
      for (const Bond& b : *set) {
        const Particle &p = at(b.p), &q = at(b.q);
        const double gap = std::hypot(p.x_um - q.x_um, p.y_um - q.y_um) - p.r_um - q.r_um;
        CHECK(gap <= 0.025 + 1e-9);
      }
    // Collagen particles only where asked: 7 per hole slot.
    const bool holes = as == "collagen" && pattern != "interstitial";
    if (collagen == "particles" && holes) {
      CHECK(t.collagen.size() == 7 * (25 * 11 - t.cell_count()));
    } else {
      CHECK(t.collagen.empty());
    }
    if (collagen == "particles" && as == "collagen") CHECK_FALSE(t.collagen_bonds.empty());
  });
}

TEST_CASE("dem sheets: every pattern and collagen mode builds a DEM body that stays at rest") {
  // Bonds form unloaded (reference gap = the gap at the start), so at length
  // ratio 1 no force acts but the round-off of placing a clump's particles
  // from its pose (~1e-16 of 1e-4 m): over 200 steps nothing may move more
  // than 1e-6 um and the strain must stay below 1e-12.
  for_each_fibrosis([](const std::string& pattern, const std::string& as, const std::string& collagen) {
    const Tissue t = testing::build_tissue(sheet(0.3, 0.75, fibrosis(pattern, as, collagen)), 2);
    DemSolver dem(t, DemSpec{});
    const std::vector<double> ratio(t.cell_count(), 1.0);
    for (int k = 0; k < 200; ++k) {
      dem.set_cell_length_ratios(ratio);
      dem.step(dem.step_ms());
    }
    CHECK(max_displacement_um(dem, t) < 1e-6);
    for (double e : dem.strain()) CHECK(std::abs(e) < 1e-12);
    CHECK(dem.broken_bonds() == 0);
  });
}

TEST_CASE("dem sheets: collagen contacts take the collagen's stiffness, the others keep theirs") {
  const Tissue voids = testing::build_tissue(sheet(0.3, 0.75, fibrosis("diffuse", "collagen", "voids")), 3);
  const Tissue particles = testing::build_tissue(sheet(0.3, 0.75, fibrosis("diffuse", "collagen", "particles")), 3);
  REQUIRE_FALSE(particles.collagen.empty());
  DemSpec spec;
  spec.collagen_stiffness_factor = 3.0;
  const DemSolver with(particles, spec), without(voids, spec);
  // The cells' bonds are the same, first, with the same stiffness; the bonds
  // through collagen follow, at 3 x 26 N/m (ks 3 x 0.26).
  REQUIRE(with.bonds().size() == particles.bonds.size() + particles.collagen_bonds.size());
  REQUIRE(without.bonds().size() == voids.bonds.size());
  REQUIRE(particles.bonds.size() == voids.bonds.size());
  for (std::size_t k = 0; k < with.bonds().size(); ++k) {
    const bool collagen = k >= particles.bonds.size();
    CHECK(with.bonds().kn[k] == (collagen ? 3.0 * 26.0 : 26.0));
    CHECK(with.bonds().ks[k] == (collagen ? 3.0 * 0.26 : 0.26));
  }
  for (std::size_t k = 0; k < without.bonds().size(); ++k) CHECK(without.bonds().kn[k] == with.bonds().kn[k]);
  // The collagen's disks are bodies of their own; the cells' bodies come first, unchanged.
  CHECK(with.body_count() == without.body_count() + particles.collagen.size());
  CHECK(with.particles().size() == particles.particles.size());
  // Septa of interstitial collagen, in either mode: bonds through collagen
  // between two cells' particles (3 per cut side coupling), no coupling.
  const Tissue septa = testing::build_tissue(sheet(0.6, 1.5, fibrosis("interstitial", "collagen", "particles")), 5);
  const Tissue cut = testing::build_tissue(sheet(0.6, 1.5, fibrosis("interstitial", "collagen", "voids")), 5);
  const Tissue plain = testing::build_tissue(sheet(0.6, 1.5), 5);
  CHECK(septa.collagen.empty());
  CHECK(septa.cell_edges == cut.cell_edges);
  CHECK(septa.collagen_bonds.size() == cut.collagen_bonds.size());
  CHECK(septa.collagen_bonds.size() == 3 * (plain.cell_edges.size() - septa.cell_edges.size()));
  CHECK(septa.bonds.size() + septa.collagen_bonds.size() == plain.bonds.size());
  const DemSolver septa_dem(septa, spec);
  CHECK(septa_dem.bonds().kn[septa.bonds.size()] == 3.0 * 26.0);
}

TEST_CASE("dem sheets: a collagen stiffness of 0, collagen particles of fibroblasts, a DEM too large are refused") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "sheet", "duration_ms": 1,
    "effects": ["electrophysiology", "coupling", "contraction", "mechanics"],
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.2, "length_mm": 0.5,
               "fibrosis": {"density": 0.2, "pattern": "diffuse", "collagen": "particles"}},
    "cells": {"myocyte": {"model": "colman", "myofilament": {"model": "rice"}}},
    "mechanics": {"collagen_stiffness_factor": 0},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01}
  })");
  CHECK_THROWS_WITH_AS(parse_scene(m),
                       doctest::Contains("mechanics.collagen_stiffness_factor: expected a number in [1e-06, 1000000], got 0"),
                       ManifestError);
  m["mechanics"]["collagen_stiffness_factor"] = -2;
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("got -2"), ManifestError);
  m["mechanics"].erase("collagen_stiffness_factor");
  m["tissue"]["fibrosis"]["as"] = "fibroblasts";
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("tissue.fibrosis.collagen: collagen particles need `as: collagen`"),
                       ManifestError);
  // The DEM's memory: 370 bytes a particle and 170 a bond (resource_estimate.cpp), collagen's counted.
  const Tissue t = testing::build_tissue(sheet(0.2, 0.5, fibrosis("diffuse", "collagen", "particles")));
  const double bytes = 370.0 * static_cast<double>(t.particles.size() + t.collagen.size()) +
                       170.0 * static_cast<double>(t.bonds.size() + t.collagen_bonds.size());
  CHECK(dem_memory(t).bytes == bytes);
  CHECK_NOTHROW(check_dem_memory(t, bytes / 0.8));
  CHECK_THROWS_WITH_AS(check_dem_memory(t, bytes), doctest::Contains("tissue: mechanics on this tissue needs about"),
                       ManifestError);
}

TEST_CASE("dem sheets: mass scaling and multirate hold the acceptance bounds on fibrotic sheets" * doctest::test_suite("slow")) {
  // 0.3 x 0.75 mm, 20 % patchy fibrosis (l = 0.2 mm), as fibroblasts (7-disk
  // chains) and as collagen particles (stiffer by 55/18): a twitch of 150 ms.
  for (const std::string as : {"fibroblasts", "collagen"}) {
    CAPTURE(as);
    json f = {{"density", 0.2}, {"pattern", "patchy"}, {"as", as}, {"correlation_length_mm", 0.2}};
    if (as == "collagen") f["collagen"] = "particles";
    const Tissue t = build_tissue(sheet(0.3, 0.75, f), 4);
    DemSpec native_spec;
    DemSpec scaled_spec = native_spec, multirate_spec = native_spec;
    scaled_spec.mass_scaling = 0.005;
    multirate_spec.multirate = true;
    const StrainCourse native = twitch(t, native_spec, 150);
    const StrainCourse scaled = twitch(t, scaled_spec, 150), multirate = twitch(t, multirate_spec, 150);
    MESSAGE(as, ": step native ", native.step_ms, " ms, scaled ", scaled.step_ms, " ms, multirate ", multirate.step_ms,
            " ms with ", multirate.light_bodies, " light bodies; steps ", native.steps, ", ", scaled.steps, ", ",
            multirate.steps, " (+", multirate.substeps, " substeps)");
    check_within_bounds(scaled, native);
    check_within_bounds(multirate, native);
  }
}

TEST_CASE("dem sheets: an electromechanical sheet gives the same bits on one thread and on two" * doctest::test_suite("threads")) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "em_sheet", "duration_ms": 40, "seed": 2,
    "effects": ["electrophysiology", "coupling", "contraction", "mechanics"],
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.3, "length_mm": 0.75,
               "fibrosis": {"density": 0.2, "pattern": "diffuse", "collagen": "particles"}},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013_caf", "myofilament": "rice"}},
    "coupling": {"D_m_nS": 300},
    "stimulus": [{"target": {"y_max_frac": 0.2}, "start_ms": 1, "duration_ms": 2, "amplitude_pA": 4000}],
    "mechanics": {"skip_at_rest": false},
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"traces": {"cells": [0, 40], "variables": ["V"], "every_ms": 1}}
  })");
  auto run = [&m](int threads) {
    m["solver"]["threads"] = threads;
    Simulation sim(parse_scene(m));
    sim.run();
    return std::make_pair(sim.trace_column_names(), sim.trace_samples());  // V and the strain eps_xx, yy, xy
  };
  const auto one = run(1), two = run(2);
  const auto& names = one.first;
  const auto yy = std::find(names.begin(), names.end(), "eps_yy") - names.begin();
  REQUIRE(static_cast<std::size_t>(yy) < names.size());
  CHECK(std::abs(one.second[yy].back()) > 0);  // the sheet did move
  CHECK(one == two);
}
