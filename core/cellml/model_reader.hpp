// Reads a CellML document (1.0, 1.1 or 2.0) into its components' variables
// (with units resolved), connections and equations. Nothing is interpreted
// here beyond the document's own structure; model_analysis.hpp does that.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cellml/mathml.hpp"
#include "cellml/units.hpp"

namespace fibrodem::cellml {

struct Variable {
  std::string component;
  std::string name;
  std::string units_name;
  Unit unit;
  std::string initial;  // initial_value as written (a number or, 1.1/2.0, a variable's name); "" if none
  std::string path;
  // Its identifier (cmeta:id in 1.0/1.1, id in 2.0; "" if none) and the
  // oxmeta terms the document's RDF gives it (membrane_voltage, ...).
  std::string id;
  std::vector<std::string> oxmeta;
  std::string qualified() const { return component + "." + name; }
};

struct Connection {
  int a = -1, b = -1;  // variable indices
  std::string path;    // of the map_variables element
};

// lhs = rhs, or d(lhs)/d(bvar) = rhs; names are those of the equation's component.
struct Equation {
  std::string component;
  int lhs = -1;
  bool ode = false;
  int bvar = -1;
  Expr rhs;
  std::string path;
};

struct Document {
  std::string file;
  std::string version;  // "1.0", "1.1" or "2.0"
  std::string model_name;
  std::vector<Variable> variables;
  std::map<std::pair<std::string, std::string>, int> index;  // (component, name) -> variable
  std::vector<Connection> connections;
  std::vector<Equation> equations;
  std::string text;  // the file's text (for line numbers)
  std::map<std::pair<std::string, std::string>, Unit> number_units;  // (component, units name) of <cn>s

  int find(const std::string& component, const std::string& name) const;
};

// Reads and checks the document's structure; ImportError names the element.
Document read_cellml(const std::filesystem::path& file);

}  // namespace fibrodem::cellml
