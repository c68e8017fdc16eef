// Holes of the cell triangulation (measure/cell_triangles.hpp): regions
// without triangles enclosed by tissue, such as a collagen scar or a cleft of
// fibrosis. A rotor turning around one has its phase singularity inside it,
// where no triangle of cells can hold it; the phase's winding around the
// hole's rim finds it (measure/phase_singularities.hpp).
//
// The rim of the triangulated region is the chain of triangle sides that no
// other triangle shares in the opposite direction. Walked with the tissue on
// the left, an outer rim runs counter-clockwise (positive signed area) and a
// hole's rim clockwise (negative). Where two rims touch at one cell (a
// pinch), the walk keeps the same region without tissue on its right (the
// smallest counter-clockwise turn from the way back), so two holes that
// touch, or a hole touching the tissue's edge, are walked apart.
//
// A component of tissue inside a hole (an island) carries its own charge on
// its outer rim; the winding around the hole's rim counts it as well, so the
// hole's own charge is that winding less the islands' (those directly inside
// it, not those inside an island's own holes). An island touching the hole's
// rim at a cell is walked as part of that rim, which then excludes it.
#pragma once

#include <array>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

// A closed loop of cells, counter-clockwise, its last cell joined to its first.
using CellLoop = std::vector<int>;

struct CellHole {
  CellLoop rim;                   // counter-clockwise around the hole
  std::vector<CellLoop> islands;  // outer rims directly inside it, counter-clockwise
  double x_mm = 0, y_mm = 0;      // the centroid of the area the rim encloses
  double area_mm2 = 0;            // the area the rim encloses
  double reach_mm = 0;            // from the centroid to the farthest rim cell
};

std::vector<CellHole> cell_holes(const Tissue& tissue, const std::vector<std::array<int, 3>>& triangles);

}  // namespace fibrodem
