// The expression writer: a MathML expression tree as C++ for the generated
// plugin, in double where it depends on constants and time alone and in SIMD
// lanes (the model's number type R) where it depends on a cell's states or
// inputs.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cellml/interface_map.hpp"
#include "cellml/model_analysis.hpp"

namespace fibrodem::cellml {

struct Code {
  std::string text;
  bool lane = false;     // depends on a cell's state or input: lanes of R
  bool boolean = false;  // a condition
};

// A name as a C++ identifier (letters, digits, '_').
std::string sanitize(const std::string& s);

// One C++ identifier per quantity: the CellML name, or component_name where
// that is taken or reserved; time is `time` and the membrane potential v
// (if >= 0) is `V`, whatever its CellML name.
std::vector<std::string> identifiers(const Model& model, int v);

class ExpressionWriter {
 public:
  // `lane` marks the quantities held in lanes; `ident` names every quantity.
  ExpressionWriter(const Model& model, const InterfaceMap& boundary, const std::vector<bool>& lane,
                   const std::vector<std::string>& ident)
      : m_(model), b_(boundary), lane_(lane), ident_(ident) {}

  Code emit(const Expr& e);

  // A divide node the writer offers to be rewritten first (singularities.hpp).
  std::function<std::optional<Code>(const Expr&)> rewrite_divide;

  static std::string as_lane(const Code& c) { return c.lane ? c.text : "R(" + c.text + ")"; }
  static std::string as_mask(const Code& c) { return c.lane ? c.text : "(R(" + c.text + " ? 1.0 : 0.0) != R(0.0))"; }

 private:
  Code variable(int v) const;
  Code piecewise(const Expr& e);
  Code derivative(const Expr& e);

  const Model& m_;
  const InterfaceMap& b_;
  const std::vector<bool>& lane_;
  const std::vector<std::string>& ident_;
};

}  // namespace fibrodem::cellml
