// Recursive coordinate bisection of the cells: the cells split into parts
// by straight cuts through their centres, each cut across the longer side
// of its cells' bounding box, measured in cells (docs/guide/parallel.md,
// Design 2). It reads the centres alone, never the cell graph (cut over
// ranks that each hold some of the cells, only its medians would need
// reducing); the parts are compact, as a spatial split of the DEM wants.
#pragma once

#include <vector>

namespace fibrodem {

// The cells' spacing along x and y [um]: a cut across x passes between
// columns pitch_x_um apart, so the box's sides are compared in cells.
struct CellPitch {
  double x_um = 1, y_um = 1;
};

// Per cell (centres x_um[i], y_um[i]), its part in [0, parts): part p holds
// n / parts cells, one more for the first n % parts parts. Each cut puts the
// cells below a median along its axis (ties: the lower cell number) on the
// side of the lower parts, so the result is a function of the centres alone.
std::vector<int> bisect_coordinates(const std::vector<double>& x_um, const std::vector<double>& y_um, CellPitch pitch,
                                    int parts);

}  // namespace fibrodem
