// Triangles over the cell centres on which phase singularities are found
// (measure/phase_singularities.hpp): a triangulation of the cell graph
// itself, not of the plane, so that no triangle spans a gap the tissue has
// no cells in (a fibroblast cleft, the space outside a patch).
//
// Triangles are
//   - every three mutually adjacent cells (3-cliques of cell_edges): the
//     staggered columns of the column tissues give these, as does any
//     contact graph of cells packed in a plane;
//   - every chordless 4-cycle of cell_edges (a square grid's cell) split
//     along its shorter diagonal into two, so that a graph of 4-neighbours
//     is covered as well.
// Each triangle is ordered counter-clockwise (positive signed area), so a
// charge summed along it has one orientation everywhere. Degenerate
// triangles (collinear centres, area below 1e-9 um^2) are left out.
#pragma once

#include <array>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

std::vector<std::array<int, 3>> cell_triangles(const Tissue& tissue);

}  // namespace fibrodem
