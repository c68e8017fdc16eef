// A colman2013 strand paced at one end, and the conduction velocity fitted
// over part of it: the scene of the tests of heterogeneous coupling
// (tests/coupling/test_coupling_regions.cpp, tests/coupling/test_coupling_field.cpp).
#pragma once

#include <doctest/doctest.h>

#include "support/scenes.hpp"

namespace fibrodem::testing {

// `cells` colman2013 myocytes (125 um each, along y at x = 0), D_m_nS 1000,
// paced at the first two; Rush-Larsen at 0.01 ms for 40 ms.
inline json paced_strand(int cells) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "strand", "seed": 1, "duration_ms": 40,
    "tissue": {"builder": "strand", "type": "myocyte"},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0, 1], "start_ms": 1, "duration_ms": 2, "amplitude_pA": 8000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"report": false}
  })");
  m["tissue"]["cells"] = cells;
  return m;
}

// CV [cm/s] of the cells whose centres lie in [from, to] mm: 1 / the
// least-squares slope of activation time against position. Every such cell
// must have fired.
inline double cv_between(const Simulation& sim, double from_mm, double to_mm) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& b : sim.biomarkers()) {
    const double y = sim.tissue().y_um[static_cast<std::size_t>(b.cell)];
    if (y < 1000 * from_mm || y > 1000 * to_mm) continue;
    REQUIRE(fired(b));
    n += 1, sx += y, sy += b.activation_ms, sxx += y * y, sxy += y * b.activation_ms;
  }
  REQUIRE(n >= 5);
  return 0.1 / ((sxy - sx * sy / n) / (sxx - sx * sx / n));  // um/ms -> cm/s
}

}  // namespace fibrodem::testing
