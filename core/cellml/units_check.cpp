#include "cellml/units_check.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

namespace fibrodem::cellml {

namespace {

Unit times(const Unit& a, const Unit& b, double exponent_b) {
  Unit u = a;
  u.scale *= std::pow(b.scale, exponent_b);
  for (const auto& [d, x] : b.dims) u.dims[d] += exponent_b * x;
  return u;
}

bool same_scale(const Unit& a, const Unit& b) { return std::fabs(a.scale / b.scale - 1.0) < 1e-9; }

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

bool has_variables(const Expr& e) {
  if (e.kind == Expr::Kind::variable) return true;
  for (const auto& a : e.args)
    if (has_variables(a)) return true;
  return false;
}

class Checker {
 public:
  Checker(const Model& m, const Evaluator& numbers, const std::string& component)
      : m_(m), numbers_(numbers), component_(component) {}
  std::vector<UnitIssue> issues;

  // The expression's unit; nullopt where it cannot be known (a power with a
  // variable exponent), which then matches anything.
  std::optional<Unit> unit(const Expr& e) {
    switch (e.kind) {
      case Expr::Kind::number: {
        if (e.units.empty()) return std::nullopt;  // 1.x requires units; 2.0 numbers without are free
        const auto it = m_.doc.number_units.find({component_, e.units});
        return it == m_.doc.number_units.end() ? std::nullopt : std::optional<Unit>(it->second);
      }
      case Expr::Kind::variable: return m_.doc.variables[e.var].unit;
      case Expr::Kind::constant: return Unit{};
      case Expr::Kind::piecewise: {
        const std::size_t pieces = (e.args.size() - (e.has_otherwise ? 1 : 0)) / 2;
        std::vector<const Expr*> values;
        for (std::size_t i = 0; i < pieces; ++i) {
          values.push_back(&e.args[2 * i]);
          unit(e.args[2 * i + 1]);
        }
        if (e.has_otherwise) values.push_back(&e.args.back());
        return same(values, e.path, "the values of a piecewise");
      }
      case Expr::Kind::apply: break;
    }
    const std::string& op = e.op;
    if (op == "plus" || op == "minus" || op == "min" || op == "max" || op == "rem") {
      std::vector<const Expr*> all;
      for (const auto& a : e.args) all.push_back(&a);
      return same(all, e.path, "the operands of <" + op + ">");
    }
    if (op == "eq" || op == "neq" || op == "gt" || op == "lt" || op == "geq" || op == "leq") {
      same({&e.args[0], &e.args[1]}, e.path, "the operands of <" + op + ">");
      return Unit{};
    }
    if (op == "and" || op == "or" || op == "xor" || op == "not") {
      for (const auto& a : e.args) unit(a);
      return Unit{};
    }
    if (op == "times" || op == "divide") {
      std::optional<Unit> u = Unit{};
      for (std::size_t i = 0; i < e.args.size(); ++i) {
        const auto a = unit(e.args[i]);
        if (!a) u = std::nullopt;
        else if (u) u = times(*u, *a, op == "divide" && i > 0 ? -1.0 : 1.0);
      }
      return u;
    }
    if (op == "power" || op == "root") {
      const auto base = unit(e.args[0]);
      const auto exponent_unit = unit(e.args[1]);
      dimensionless(exponent_unit, e.args[1].path, "an exponent");
      if (!base) return std::nullopt;
      if (has_variables(e.args[1])) {
        dimensionless(base, e.args[0].path, "the base of a variable power");
        return base;
      }
      const double exponent = numbers_.eval(e.args[1]);  // a constant expression such as -1
      const double p = op == "power" ? exponent : 1.0 / exponent;
      return times(Unit{}, *base, p);
    }
    if (op == "abs" || op == "floor" || op == "ceiling") return unit(e.args[0]);
    // exp, ln, log and the trigonometric functions: dimensionless in and out.
    for (const auto& a : e.args) dimensionless(unit(a), a.path, "the argument of <" + op + ">");
    return Unit{};
  }

  void compare(const std::optional<Unit>& lhs, const std::optional<Unit>& rhs, const std::string& path,
               const std::string& what) {
    if (!lhs || !rhs) return;
    if (!lhs->same_dims(*rhs))
      issues.push_back({path, what + ": " + lhs->dims_text() + " against " + rhs->dims_text(), true});
    else if (!same_scale(*lhs, *rhs))
      issues.push_back({path, what + ": the same dimension at " + number(lhs->scale) + " and " + number(rhs->scale) +
                                  " times " + lhs->dims_text() + " (CellML uses the numbers as written)",
                        false});
  }

 private:
  std::optional<Unit> same(const std::vector<const Expr*>& operands, const std::string& path, const std::string& what) {
    std::optional<Unit> first;
    for (const Expr* o : operands) {
      const auto u = unit(*o);
      if (!first) first = u;
      else compare(first, u, path, what + " differ in units");
    }
    return first;
  }
  void dimensionless(const std::optional<Unit>& u, const std::string& path, const std::string& what) {
    if (u && !u->same_dims(Unit{}))
      issues.push_back({path, what + " is not dimensionless (" + u->dims_text() + ")", true});
  }

  const Model& m_;
  const Evaluator& numbers_;
  std::string component_;
};

}  // namespace

std::vector<UnitIssue> check_equation_units(const Model& m) {
  std::vector<UnitIssue> all;
  const Evaluator numbers(m);
  for (const auto& eq : m.doc.equations) {
    Checker c(m, numbers, eq.component);
    const auto rhs = c.unit(eq.rhs);
    Unit lhs = m.doc.variables[eq.lhs].unit;
    if (eq.ode) lhs = times(lhs, m.doc.variables[eq.bvar].unit, -1.0);
    c.compare(lhs, rhs, eq.path, "the two sides of the equation differ in units");
    all.insert(all.end(), c.issues.begin(), c.issues.end());
  }
  return all;
}

}  // namespace fibrodem::cellml
