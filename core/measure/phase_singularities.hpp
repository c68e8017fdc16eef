// Phase singularities (PS) of a field of cells, frame by frame:
//
// Phase from V by time-delay embedding (Gray, Pertsov & Jalife 1998, Nature
// 392:75, who take the phase of each site's signal in the plane of the
// signal against its delayed copy; Clayton, Zhuchkova & Panfilov 2006, Prog
// Biophys Mol Biol 90:378, review the method, its delay and its origin):
//   phase = atan2(V(t - tau) - V*, V(t) - V*)
// V* must lie inside the loop the AP traces in that plane (between rest and
// plateau) and tau must be shorter than the AP, so that the point circles V*
// once per beat; the phase then increases through (-pi, pi] once a beat.
//
// Topological charge of a triangle of cells (a, b, c, counter-clockwise):
//   n = (1 / 2 pi) (w(p_b - p_a) + w(p_c - p_b) + w(p_a - p_c))
// with w the difference wrapped into (-pi, pi]: the discrete line integral
// of the phase gradient around the triangle (Gray et al. 1998; Clayton et
// al. 2006). n is an integer; a triangle with
// |n| = 1 holds a PS, of chirality n (+1: the phase increases
// counter-clockwise around it), placed at the triangle's centroid.
#pragma once

#include <array>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

// The phase [rad] in (-pi, pi] of a sample V(t) with its delayed sample V(t - tau).
double embedding_phase(double V_mV, double V_delayed_mV, double V_star_mV);

// d wrapped into (-pi, pi].
double wrap_phase(double d);

struct PhaseSingularity {
  double x_mm = 0, y_mm = 0;
  int chirality = 0;  // +1 or -1
  int triangle = 0;   // index into the triangles searched
};

// The triangle's charge, rounded to the nearest integer.
int triangle_charge(const std::array<int, 3>& triangle, const std::vector<double>& phase_rad);

// Every triangle (measure/cell_triangles.hpp) with charge +1 or -1, in
// triangle order. phase_rad per cell; a cell with a NaN phase (not yet
// sampled long enough) makes its triangles hold no PS.
std::vector<PhaseSingularity> find_phase_singularities(const Tissue& tissue,
                                                       const std::vector<std::array<int, 3>>& triangles,
                                                       const std::vector<double>& phase_rad);

}  // namespace fibrodem
