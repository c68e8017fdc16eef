// Dimensional consistency of a model's equations (CellML 1.0 section 5.2.7,
// 2.0 section 9): operands of +, -, comparisons, min/max and piecewise values
// share a dimension, arguments of exp, ln, log and trigonometric functions are
// dimensionless, and each side of an equation has the same dimension. The
// model's own numbers are used as written (CellML does not rescale inside an
// equation), so a mismatch of scale alone (mV beside V) is reported too.
//
// Each finding names the equation, the element and the two unit expressions;
// the importer warns with them (or refuses, under --strict-units). After a
// mismatch the offending sum's units are unknown (its dimension is kept when
// only the scale differed), so one slip is reported once, not again by every
// expression that uses the sum.
#pragma once

#include <string>
#include <vector>

#include "cellml/model_analysis.hpp"

namespace fibrodem::cellml {

struct UnitIssue {
  std::string equation;  // "membrane.i_b", or "membrane.d(V)/d(time)" for a rate
  std::string path;      // the element, with its line
  std::string what;      // "the operands of <minus> differ in dimension", "the argument of <exp> is not dimensionless"
  std::string first;     // "'V' [mV = 0.001 x ampere^-1 kilogram^1 metre^2 second^-3]"
  std::string second;    // "'Eb' [dimensionless]", or "dimensionless" where that is required
  bool dimension = false;  // a different dimension (else a different scale only)
  double factor = 1.0;     // scale only: the ratio of the larger scale to the smaller

  // "inconsistent units in EQUATION at PATH: WHAT: FIRST against SECOND"
  std::string text() const;
};

std::vector<UnitIssue> check_equation_units(const Model& model);

}  // namespace fibrodem::cellml
