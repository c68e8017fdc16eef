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
//
// A hole of the triangulation (measure/cell_holes.hpp) has the same charge
// along its rim, less its islands': a hole of charge n holds |n| PS of
// chirality sign(n), placed at the centroid of the area its rim encloses
// (a rotor anchored on a scar turns around it there). Over every triangle
// and hole, the charges add up to the winding around the tissue's outer rims.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "measure/cell_holes.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// The phase [rad] in (-pi, pi] of a sample V(t) with its delayed sample V(t - tau).
double embedding_phase(double V_mV, double V_delayed_mV, double V_star_mV);

// d wrapped into (-pi, pi].
double wrap_phase(double d);

struct PhaseSingularity {
  double x_mm = 0, y_mm = 0;
  int chirality = 0;  // +1 or -1
  int triangle = -1;  // index into the triangles searched, or -1
  int hole = -1;      // index into the holes searched, or -1
  // How far from (x, y) the singularity may lie: 0 on a triangle (it is
  // within a cell), a hole's reach (its centroid to its farthest rim cell).
  double reach_mm = 0;
};

// The charge of a closed loop of cells (counter-clockwise, the last joined to
// the first), rounded to the nearest integer; 0 if a cell's phase is NaN.
int loop_charge(std::span<const int> loop, const std::vector<double>& phase_rad);
int triangle_charge(const std::array<int, 3>& triangle, const std::vector<double>& phase_rad);
// Its rim's charge less its islands'; 0 if a cell's phase is NaN.
int hole_charge(const CellHole& hole, const std::vector<double>& phase_rad);

// Every triangle (measure/cell_triangles.hpp) with charge +1 or -1, in
// triangle order, then the PS of every hole with a charge, in hole order.
// phase_rad per cell; a cell with a NaN phase (not yet sampled long enough)
// makes its triangles and holes hold no PS.
std::vector<PhaseSingularity> find_phase_singularities(const Tissue& tissue,
                                                       const std::vector<std::array<int, 3>>& triangles,
                                                       const std::vector<double>& phase_rad,
                                                       const std::vector<CellHole>& holes = {});

// The cells a PS was found on: its triangle's, or its hole's rim.
std::span<const int> cells_around(const PhaseSingularity& ps, const std::vector<std::array<int, 3>>& triangles,
                                  const std::vector<CellHole>& holes);

}  // namespace fibrodem
