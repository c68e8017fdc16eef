// coupling.D_m_side_nS: myocytes joined side to side (across the fibres) get
// a conductance of their own (tissue/tissue.hpp end_to_end). Known answers:
// the brick sheet's junctions counted by hand; a column cut off from its
// neighbours; the same bits when it is left unset; and the ratio of
// conduction velocities across and along the fibres against the continuum
// limit of the brick lattice.
#include <doctest/doctest.h>

#include <cmath>
#include <iomanip>

#include "measure/conduction_velocity.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// A fibrotic_sheet without fibrosis: `width_mm` across the fibres (x),
// `length_mm` along them (y), paced in a band 0.3 mm deep along one edge.
json sheet(double width_mm, double length_mm, bool paced_at_left) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "sheet", "seed": 1, "duration_ms": 40,
    "tissue": {"builder": "fibrotic_sheet"},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013"}},
    "coupling": {"D_m_nS": 1000},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"report": false}
  })");
  m["tissue"]["width_mm"] = width_mm;
  m["tissue"]["length_mm"] = length_mm;
  const json band = paced_at_left ? json{{"x_min_mm", -1}, {"x_max_mm", 0.3}, {"y_min_mm", -1}, {"y_max_mm", 100}}
                                  : json{{"x_min_mm", -1}, {"x_max_mm", 100}, {"y_min_mm", -1}, {"y_max_mm", 0.3}};
  m["stimulus"] = json::array({{{"target", band}, {"start_ms", 1}, {"duration_ms", 2}, {"amplitude_pA", 8000}}});
  return m;
}

// Conduction velocity [cm/s] of the first beat along x (across) or y (along
// the fibres), fitted as summary.json's is, away from the paced band.
double cv_cm_per_s(const json& m, bool across) {
  Simulation sim(parse_scene(m));
  sim.run();
  const Tissue& t = sim.tissue();
  std::vector<ConductionSample> samples;
  for (const auto& b : sim.biomarkers()) {
    const auto c = static_cast<std::size_t>(b.cell);
    const double position = across ? t.x_um[c] : t.y_um[c];
    samples.push_back({position, b.activation_ms, position <= 300, fired(b)});
  }
  const auto fit = fit_conduction_velocity(samples);
  REQUIRE(fit);
  return fit->cv_cm_per_s;
}

}  // namespace

TEST_CASE("a brick sheet's junctions: each cell and the one above it end to end, the rest side to side") {
  // 10 columns of 15 cells (0.25 x 2 mm: the odd columns' half shift takes
  // half a cell of the length): 10 x 14 end to end; between two columns, a
  // cell touches the two of the half-shifted column beside it, 2 x 15 - 1
  // pairs: 9 x 29 side to side.
  const Tissue t = testing::build_tissue({{"builder", "fibrotic_sheet"}, {"width_mm", 0.25}, {"length_mm", 2}}, 1);
  REQUIRE(t.cell_count() == 150);
  int ends = 0, sides = 0;
  for (const auto& [i, j] : t.cell_edges) {
    if (end_to_end(t, i, j)) {
      ++ends;
      CHECK(j == i + 1);  // cells are numbered up each column
      CHECK(t.x_um[static_cast<std::size_t>(i)] == t.x_um[static_cast<std::size_t>(j)]);
    } else {
      ++sides;
      CHECK(std::abs(std::abs(t.x_um[static_cast<std::size_t>(i)] - t.x_um[static_cast<std::size_t>(j)]) - 23.57) < 0.01);
    }
  }
  CHECK(ends == 10 * 14);
  CHECK(sides == 9 * 29);
}

TEST_CASE("D_m_side_nS 0 keeps a wave in its column, and unset it is D_m_nS, bit for bit") {
  json m = sheet(0.12, 2, false);  // 5 columns of 15 cells
  m["duration_ms"] = 30;
  // Pace the bottom three cells of the middle column (cells 30-32).
  m["stimulus"][0]["target"] = {30, 31, 32};
  m["stimulus"][0]["amplitude_pA"] = 4000;
  m["coupling"]["D_m_side_nS"] = 0;
  {
    Simulation sim(parse_scene(m));
    sim.run();
    for (const auto& b : sim.biomarkers()) {
      CAPTURE(b.cell);
      CHECK(fired(b) == (b.cell >= 30 && b.cell < 45));  // its own column, all of it
    }
  }
  // Unset, paced along the bottom edge: every column fires, with the same
  // bits as D_m_side_nS = D_m_nS.
  const auto a = testing::scratch_dir("side_unset"), b = testing::scratch_dir("side_equal");
  m["stimulus"] = sheet(0.12, 2, false)["stimulus"];
  m["coupling"].erase("D_m_side_nS");
  m["output"]["dir"] = a.string();
  Simulation unset(parse_scene(m));
  unset.run();
  for (const auto& beat : unset.biomarkers()) CHECK(fired(beat));
  m["coupling"]["D_m_side_nS"] = 1000;
  m["output"]["dir"] = b.string();
  Simulation equal(parse_scene(m));
  equal.run();
  CHECK(testing::read_file(a / "biomarkers.csv") == testing::read_file(b / "biomarkers.csv"));
  CHECK(testing::read_file(a / "traces.csv") == testing::read_file(b / "traces.csv"));
}

TEST_CASE("conduction across and along the fibres scales with the side conductance as the brick lattice's continuum limit") {
  // The lattice's conductivity tensor in the continuum limit, the sum over a
  // cell's junctions of g d d^T (over twice its area): two end to end at
  // dy = +-125 um, four side to side at (+-23.57, +-62.5) um, so
  //   sigma_yy ~ 2 g_e 125^2 + 4 g_s 62.5^2,  sigma_xx ~ 4 g_s 23.57^2,
  // and, the cells' currents being the same, CV ~ sqrt(sigma) in each direction.
  const double g_e = 1000;
  const auto sigma_yy = [&](double g_s) { return 2 * g_e * 125.0 * 125.0 + 4 * g_s * 62.5 * 62.5; };
  const auto sigma_xx = [](double g_s) { return 4 * g_s * 23.57 * 23.57; };
  double cv_y[2], cv_x[2];
  const double side[2] = {1000.0, 250.0};
  for (int k = 0; k < 2; ++k) {
    json along = sheet(0.25, 5, false), across = sheet(3, 0.5, true);
    along["coupling"]["D_m_side_nS"] = side[k];
    across["coupling"]["D_m_side_nS"] = side[k];
    cv_y[k] = cv_cm_per_s(along, false);
    cv_x[k] = cv_cm_per_s(across, true);
    MESSAGE(std::setprecision(10), "D_m_side_nS ", side[k], ": CV along ", cv_y[k], " cm/s, across ", cv_x[k], " cm/s, ratio ",
            cv_x[k] / cv_y[k], ", continuum ", std::sqrt(sigma_xx(side[k]) / sigma_yy(side[k])));
  }
  // A quarter of the side conductance: half the speed across (measured
  // 2.07x, the lattice being a little more discrete across at 250 nS), and
  // along by the side junctions' share of sigma_yy (measured within 0.5 %).
  CHECK(cv_x[0] / cv_x[1] == doctest::Approx(std::sqrt(sigma_xx(side[0]) / sigma_xx(side[1]))).epsilon(0.05).scale(0));
  CHECK(cv_y[0] / cv_y[1] == doctest::Approx(std::sqrt(sigma_yy(side[0]) / sigma_yy(side[1]))).epsilon(0.02).scale(0));
  // The ratio itself is below the continuum's (0.201 against 0.218 with equal
  // conductances): discrete cells conduct across more slowly than a
  // continuum of the same conductivity. Within 15 %.
  for (int k = 0; k < 2; ++k) {
    const double continuum = std::sqrt(sigma_xx(side[k]) / sigma_yy(side[k]));
    CHECK(cv_x[k] / cv_y[k] < continuum);
    CHECK(cv_x[k] / cv_y[k] > 0.85 * continuum);
  }
}
