// coupling.field: a map of how much each junction conducts, relative to the
// conductances the section and its regions give it (a border zone's
// gradient, a bundle or a scar traced from an image). The map is a grid of
// scale factors over a rectangle; a junction whose midpoint (between the two
// cells' centres) lies in the rectangle has its conductance multiplied by the
// map's value there, a junction outside keeps its own.
//
// Grid: `rows` x `columns` samples, the first row at y_mm[0] and the last at
// y_mm[1] (along the fibres), the first column at x_mm[0] and the last at
// x_mm[1]; samples equally spaced, corner to corner, so a grid of 2 x 2 is
// the rectangle's four corners. One row (or column) is constant along y
// (or x). Between samples: `bilinear` (default) or `nearest`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

struct CouplingField {
  enum class Between { bilinear, nearest };
  double x_min_um = 0, x_max_um = 0, y_min_um = 0, y_max_um = 0;
  int rows = 0, columns = 0;
  std::vector<double> scale;  // row after row: scale[row * columns + column]
  Between between = Between::bilinear;
  std::string path;  // coupling.field, for messages

  bool contains(double x_um, double y_um) const {
    return x_um >= x_min_um && x_um <= x_max_um && y_um >= y_min_um && y_um <= y_max_um;
  }
  // The map's value at a point it contains.
  double scale_at(double x_um, double y_um) const;
};

// Reads coupling.field: `x_mm`, `y_mm` ([min, max]), the samples either
// inline (`scale`: a list of rows, each a list of numbers) or in a file
// (`file`: CSV, one row of the grid a line, values separated by commas;
// lines that are empty or start with '#' are skipped; a path relative to the
// working directory, as every path of a manifest), and `between`. Every
// value finite and >= 0; every row as long as the first. Errors name the
// path and, for a file, its line.
CouplingField read_coupling_field(const json& field, const std::string& path);

}  // namespace fibrodem
