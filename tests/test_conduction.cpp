// Conduction velocity: the fit on synthetic activation times, and a uniform
// myocyte strand whose CV converges as the step shrinks.
#include <doctest/doctest.h>

#include <cmath>

#include "measure/conduction_velocity.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_CASE("the CV fit recovers a known velocity and ignores stimulated, edge and silent cells") {
  // 50 cm/s = 500 um/ms from a stimulus at the top (y = 10000 um) downwards.
  std::vector<ConductionSample> cells;
  for (int k = 0; k <= 100; ++k) {
    const double y = 100.0 * k;
    const bool stimulated = y >= 9000;
    const double t = 5.0 + (9000 - std::min(y, 9000.0)) / 500.0 + (k % 2 ? 0.05 : -0.05);
    cells.push_back({y, stimulated ? 1.0 : t, stimulated, true});
  }
  cells[3].activated = false;
  cells[3].activation_ms = 1e6;  // would spoil the fit if used
  const auto fit = fit_conduction_velocity(cells);
  REQUIRE(fit.has_value());
  CHECK(fit->cv_cm_per_s == doctest::Approx(50.0).epsilon(0.01));
  CHECK(fit->r_squared > 0.99);
  CHECK(fit->from_um == doctest::Approx(900));
  CHECK(fit->to_um == doctest::Approx(8100));
  // No stimulated cell: no direction, no fit.
  for (auto& c : cells) c.stimulated = false;
  CHECK_FALSE(fit_conduction_velocity(cells).has_value());
}

namespace {
double strand_cv(double dt_ms, const std::string& scheme, double D_m_nS = 1000, double coupling_dt_ms = 0) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "strand_cv", "duration_ms": 60,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 40},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0, 1, 2, 3], "start_ms": 1, "duration_ms": 2, "amplitude_pA": 8000}],
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 0.1}}
  })");
  m["solver"] = {{"method", "rush_larsen"}, {"dt_ms", dt_ms}};
  m["coupling"]["scheme"] = scheme;
  m["coupling"]["D_m_nS"] = D_m_nS;
  m["coupling"]["dt_ms"] = coupling_dt_ms;
  Simulation sim(parse_scene(m));
  sim.run();
  const json summary = sim.summary();
  REQUIRE(summary["cv_cm_per_s"].is_number());
  return summary["cv_cm_per_s"].get<double>();
}
}  // namespace

TEST_CASE("a uniform myocyte strand conducts at a CV that converges as the step shrinks") {
  // D_m = 1000 nS on 100 pF: explicit coupling is stable below 2/lambda = 0.05 ms.
  const double cv_a = strand_cv(0.02, "explicit");
  const double cv_b = strand_cv(0.01, "explicit");
  const double cv_c = strand_cv(0.005, "explicit");
  CAPTURE(cv_a);
  CAPTURE(cv_b);
  CAPTURE(cv_c);
  // Differences shrink by about half per halving (a first-order scheme).
  CHECK(std::abs(cv_c - cv_b) < 0.7 * std::abs(cv_b - cv_a));
  CHECK(std::abs(cv_c - cv_b) / cv_c < 0.02);
}

TEST_CASE("implicit coupling at a 10x larger step agrees with explicit coupling within 2 % in CV") {
  const double explicit_fine = strand_cv(0.001, "explicit");
  const double implicit_coarse = strand_cv(0.01, "implicit");
  CAPTURE(explicit_fine);
  CAPTURE(implicit_coarse);
  CHECK(std::abs(implicit_coarse - explicit_fine) / explicit_fine < 0.02);
}

TEST_CASE("with 10x stronger coupling, explicit coupling at 0.01 ms blows up, implicit stays accurate") {
  // D_m = 10^4 nS: lambda <= 4 * 10^4 / 100 = 400 /ms, explicit limit 0.005 ms.
  CHECK_THROWS_WITH(strand_cv(0.01, "explicit", 1e4), doctest::Contains("blow-up"));
  const double explicit_fine = strand_cv(0.001, "explicit", 1e4);
  const double implicit_coarse = strand_cv(0.01, "implicit", 1e4);
  CAPTURE(explicit_fine);
  CAPTURE(implicit_coarse);
  CHECK(explicit_fine > 1.5 * strand_cv(0.001, "explicit"));  // CV grows with coupling (~ sqrt(D))
  CHECK(std::abs(implicit_coarse - explicit_fine) / explicit_fine < 0.02);
}

TEST_CASE("multirate coupling: the gap current held over 4 cell steps changes CV by under 1 %") {
  const double every_step = strand_cv(0.005, "explicit");
  const double every_fourth = strand_cv(0.005, "explicit", 1000, 0.02);
  CAPTURE(every_step);
  CAPTURE(every_fourth);
  CHECK(every_fourth != every_step);  // it really is updated less often
  CHECK(std::abs(every_fourth - every_step) / every_step < 0.01);
  CHECK_THROWS_WITH_AS(strand_cv(0.005, "explicit", 1000, 0.012), doctest::Contains("coupling.dt_ms"), ManifestError);
}
