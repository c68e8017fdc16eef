// Dimensional consistency of a model's equations (CellML 1.0 section 5.2.7,
// 2.0 section 9): operands of +, -, comparisons, min/max and piecewise values
// share a dimension, arguments of exp, ln, log and trigonometric functions are
// dimensionless, and each side of an equation has the same dimension. The
// model's own numbers are used as written (CellML does not rescale inside an
// equation), so a mismatch of scale alone (mV beside V) is reported too.
#pragma once

#include <string>
#include <vector>

#include "cellml/model_analysis.hpp"

namespace fibrodem::cellml {

struct UnitIssue {
  std::string path;     // the element
  std::string message;
  bool dimension = false;  // a different dimension (else a different scale only)
};

std::vector<UnitIssue> check_equation_units(const Model& model);

}  // namespace fibrodem::cellml
