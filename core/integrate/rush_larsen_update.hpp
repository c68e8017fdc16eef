// The Rush-Larsen update (Rush & Larsen 1978, IEEE TBME 25:389) of SIMD lanes
// of one state from its linear form dy/dt = A + B y, held over the step dt:
//   y' = y_inf + (y0 - y_inf) E,  y_inf = -A/B,  E = exp(B dt)
// (exact while A and B hold); where B = 0, Euler: y0 + dt A. E is passed in
// so that a caller can share one exp between steps (exp(B h) = exp(B h/2)^2).
#pragma once

#include "model/simd.hpp"

namespace fibrodem {

inline simd::Real rush_larsen_update(const simd::Real& y0, const simd::Real& A, const simd::Real& B,
                                     const simd::Real& E, double dt) {
  const auto moving = B != 0.0;
  const simd::Real y_inf = -A / simd::select(moving, B, 1.0);
  return simd::select(moving, y_inf + (y0 - y_inf) * E, y0 + dt * A);
}

}  // namespace fibrodem
