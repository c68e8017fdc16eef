// MathML content markup as CellML uses it: an expression tree, read from the
// <math> elements of a component. Every node keeps its element's path so that
// whatever cannot be translated later is refused by where it is.
#pragma once

#include <string>
#include <vector>

namespace pugi {
class xml_node;
}

namespace fibrodem::cellml {

struct Expr {
  enum class Kind { number, variable, apply, piecewise, constant };
  Kind kind = Kind::number;
  // number: value; constant: op is pi, exponentiale, true, false, notanumber, infinity.
  double value = 0.0;
  std::string name;  // variable: the name in its component
  int var = -1;      // variable: the model's variable index, once resolved
  // apply: the operator element's name (plus, times, exp, root, ...);
  std::string op;
  // apply: the operands (root: the degree is appended, default 2; log: the
  // base, default 10); piecewise: value, condition, value, condition, ...,
  // then the otherwise value if has_otherwise; diff (a derivative inside an
  // expression): the variable, then the bound variable.
  std::vector<Expr> args;
  bool has_otherwise = false;
  std::string path;  // the element's path in the document, with its line
  std::string units;  // number: its cellml:units ("" if none)
};

// The operators a translated equation may use (anything else is refused).
bool supported_operator(const std::string& op);

// An element's path in the document, "/model/component[@name='m']/math/apply[3] (line 57)";
// the line is counted in the document's text.
std::string element_path(const pugi::xml_node& node, const std::string& text);
// The element's name without a namespace prefix.
std::string local_name(const pugi::xml_node& node);
// An attribute by local name (ignores its namespace prefix), or "".
std::string attribute(const pugi::xml_node& node, const std::string& name);

// Reads one expression element (apply, ci, cn, piecewise, a constant).
Expr read_expression(const pugi::xml_node& node, const std::string& text);

}  // namespace fibrodem::cellml
