// Geometry of a myocyte clump: N equal disks of radius r whose centres lie on a
// line at spacing s (docs/reference/references.md#dem-clumps, #dem-contraction-rule), and
// how it changes when the cell
// contracts with its 2D area kept.
//
// The union's area is exact for any spacing (r <= s/2 included): each disk owns
// the strip of the axis closer to its centre than to any other, and there the
// union's half-height is that disk's, so A = pi r^2 + 4(N-1) F(r, h) with
// h = min(s/2, r), F = (h sqrt(r^2-h^2) + r^2 asin(h/r))/2. (This equals
// N pi r^2 - (N-1) lens(r, s) also for s < r: the lens of disks k and k+2 lies
// inside disk k+1, so the pairwise and triple terms cancel.)
// Lengths in any unit (the solver uses metres); areas in that unit squared.
#pragma once

#include "mechanics/dem_spec.hpp"

namespace fibrodem {

struct ClumpShape {
  double r = 0, s = 0;
};

double union_area(int n, double r, double s);
double union_area_dr(int n, double r, double s);  // dA/dr at fixed s
double union_area_ds(int n, double r, double s);  // dA/ds at fixed r
// Polar second moment of the union about its centre, integral of (x^2 + y^2) dA.
double union_polar_moment(int n, double r, double s);

// The area each rule keeps: union (A), capsule 2r(N-1)s + pi r^2 (B),
// rectangle 2r(N-1)s (C; for N = 1 the radius is kept instead).
double rule_area(AreaRule rule, int n, double r, double s);

// A clump's rest shape and the area its rule keeps, computed once: the DEM
// solves every contracting myocyte's shape at every step, and recomputing
// this area took about 5 % of that solve (perf samples, Fig. 3 EM).
struct ClumpRest {
  int n = 1;
  double r0 = 0, s0 = 0, area = 0;
};
ClumpRest clump_rest(AreaRule rule, int n, double r0, double s0);

// The clump's shape at length ratio lambda = L/L0 from its rest shape (r0, s0):
// spacing mode s = s0 lambda; total mode (N-1)s + 2r = lambda ((N-1)s0 + 2r0);
// r such that rule_area is that of the rest shape. Throws std::invalid_argument
// if no such shape exists (e.g. the rectangle rule in total mode below ~0.8).
// r_guess (> 0) starts the union rule's Newton iteration (e.g. the radius at the
// previous step: a couple of iterations instead of several); the root is the same.
ClumpShape contracted_shape(AreaRule rule, LengthMode mode, const ClumpRest& rest, double lambda,
                            double r_guess = 0);
inline ClumpShape contracted_shape(AreaRule rule, LengthMode mode, int n, double r0, double s0, double lambda,
                                   double r_guess = 0) {
  return contracted_shape(rule, mode, clump_rest(rule, n, r0, s0), lambda, r_guess);
}

}  // namespace fibrodem
