// How far a DEM's particles have moved from where the tissue built them.
#pragma once

#include <algorithm>
#include <cmath>

#include "mechanics/dem_solver.hpp"

namespace fibrodem::test {

inline double max_displacement_um(const DemSolver& dem, const Tissue& t) {
  double m = 0;
  const auto& p = dem.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    m = std::max(m, std::hypot(p[i].x_um - t.particles[i].x_um, p[i].y_um - t.particles[i].y_um));
  return m;
}

}  // namespace fibrodem::test
