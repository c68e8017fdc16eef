// What a CellML document means as a system of ODEs: connected variables
// merged into quantities (with the unit conversion of each connection), each
// quantity's role (time, state, constant parameter, algebraic), and the
// algebraic equations in an order where each comes after what it uses
// (topological sort; an algebraic loop or a DAE is refused by its elements).
#pragma once

#include <string>
#include <vector>

#include "cellml/model_reader.hpp"

namespace fibrodem::cellml {

enum class Role { time, state, parameter, algebraic };

struct Quantity {
  Role role = Role::algebraic;
  int source = -1;            // the variable that defines it (its units are the quantity's)
  std::vector<int> members;   // every connected variable
  int equation = -1;          // the defining equation (state: its ODE)
  double initial = 0.0;       // state: initial value; parameter: value (source units)
  std::vector<int> uses;      // quantities its equation uses
};

struct Model {
  Document doc;
  std::vector<int> quantity_of;  // per variable
  std::vector<Quantity> quantities;
  int time = -1;
  std::vector<int> states;     // quantities, in document order
  std::vector<int> parameters;
  std::vector<int> order;      // algebraic quantities, each after those it uses
  // Initial values that name a constant of another dimension (a slip the
  // import warns of, or refuses under --strict-units): the constant's number
  // is taken as written in the variable's own units, not converted.
  std::vector<std::string> initial_value_unit_issues;

  const Variable& source(int q) const { return doc.variables[quantities[q].source]; }
  // value of variable v = value of its quantity * factor (connected units).
  double factor_to(int v) const;
  // A rate d(source)/d(time) = rhs (in the equation's own units) * this.
  double rate_factor(int q) const;
};

Model analyse(Document doc);

// 1e-9 / 1e-12 is 1000.0000000000001 in binary: conversion factors are
// rounded to 15 significant digits, which every prefix and multiplier has.
double snapped(double x);

// Numbers of a model at one point: every quantity's value from the states and
// parameters (algebraic ones in order), and any expression of it.
class Evaluator {
 public:
  explicit Evaluator(const Model& model);
  std::vector<double> values;  // per quantity
  std::vector<char> pinned;    // algebraic quantities update() leaves as they are
  void update();               // recompute algebraic quantities from the rest
  double eval(const Expr& e) const;
  double rate(int state) const;  // d(source)/d(time) in the quantity's units

 private:
  const Model& m_;
};

// Quantities that q depends on, through algebraic equations (not itself).
std::vector<bool> dependencies(const Model& model, const Expr& e);

}  // namespace fibrodem::cellml
