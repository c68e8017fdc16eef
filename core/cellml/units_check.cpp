#include "cellml/units_check.hpp"
#include "util/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace fibrodem::cellml {

namespace {

bool has_variables(const Expr& e) {
  if (e.kind == Expr::Kind::variable) return true;
  for (const auto& a : e.args)
    if (has_variables(a)) return true;
  return false;
}

bool infix(const std::string& op) { return op == "plus" || op == "minus" || op == "times" || op == "divide" || op == "power"; }

// A short infix rendering of an operand, so that a finding says which terms
// disagree ("V - Eb"); long ones are cut.
std::string term(const Expr& e) {
  switch (e.kind) {
    case Expr::Kind::number: return significant_digits(e.value, 6);
    case Expr::Kind::variable: return e.name;
    case Expr::Kind::constant: return e.op;
    case Expr::Kind::piecewise: return "piecewise(...)";
    case Expr::Kind::apply: break;
  }
  auto operand = [](const Expr& a) {
    const std::string t = term(a);
    return a.kind == Expr::Kind::apply && infix(a.op) ? "(" + t + ")" : t;
  };
  if (e.op == "minus" && e.args.size() == 1) return "-" + operand(e.args[0]);
  if (e.op == "diff") return "d(" + e.args[0].name + ")/d(" + e.args[1].name + ")";
  std::string out;
  if (infix(e.op)) {
    const std::string sep = e.op == "plus" ? " + " : e.op == "minus" ? " - " : e.op == "times" ? " * " : e.op == "divide" ? " / " : "^";
    for (std::size_t i = 0; i < e.args.size(); ++i) out += (i ? sep : "") + operand(e.args[i]);
  } else {
    out = e.op + "(";
    for (std::size_t i = 0; i < e.args.size(); ++i) out += (i ? ", " : "") + term(e.args[i]);
    out += ")";
  }
  return out.size() > 60 ? out.substr(0, 57) + "..." : out;
}

// What the checker knows of an expression's units: the unit, how the model
// writes it ("mS_per_cm2 * mV"), and whether its scale is known (not after a
// sum of terms at different scales).
struct Found {
  Unit unit;
  std::string units = "dimensionless";
  bool scale_known = true;
};

bool compound(const std::string& units) { return units.find(' ') != std::string::npos; }

Found times(const Found& a, const Found& b, double exponent_b) {
  Found f = a;
  f.unit.scale *= std::pow(b.unit.scale, exponent_b);
  for (const auto& [d, x] : b.unit.dims) f.unit.dims[d] += exponent_b * x;
  f.scale_known = a.scale_known && b.scale_known;
  const std::string b_text = compound(b.units) ? "(" + b.units + ")" : b.units;
  f.units = exponent_b == 1.0 ? a.units + " * " + b_text
            : exponent_b == -1.0 ? a.units + " / " + b_text
                                 : a.units + " * " + b_text + "^" + significant_digits(exponent_b, 6);
  return f;
}

Found raised(const Found& base, double p) {
  Found f = base;
  f.unit.scale = std::pow(base.unit.scale, p);
  for (auto& [d, x] : f.unit.dims) x *= p;
  f.units = (compound(base.units) ? "(" + base.units + ")" : base.units) + "^" + significant_digits(p, 6);
  return f;
}

// "'V' [mV = 0.001 x ampere^-1 kilogram^1 metre^2 second^-3]"
std::string described(const std::string& term_text, const Found& f) {
  const std::string units = f.scale_known ? f.unit.described_as(f.units) : f.units + " = ? x " + f.unit.dims_text();
  return "'" + term_text + "' [" + units + "]";
}

class Checker {
 public:
  Checker(const Model& m, const Evaluator& numbers, const std::string& component, const std::string& equation)
      : m_(m), numbers_(numbers), component_(component), equation_(equation) {}
  std::vector<UnitIssue> issues;

  // The expression's units; nullopt where they cannot be known (a power with
  // a variable exponent, a number without units, a sum after a mismatch),
  // which then matches anything.
  std::optional<Found> unit(const Expr& e) {
    switch (e.kind) {
      case Expr::Kind::number: {
        if (e.units.empty()) return std::nullopt;
        const auto it = m_.doc.number_units.find({component_, e.units});
        if (it == m_.doc.number_units.end()) return std::nullopt;
        return Found{it->second, e.units, true};
      }
      case Expr::Kind::variable: {
        const auto& v = m_.doc.variables[e.var];
        return Found{v.unit, v.units_name, true};
      }
      case Expr::Kind::constant: return Found{};
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
    return apply(e);
  }

  // Records a finding if a and b differ; false then.
  bool compare(const std::optional<Found>& a, const std::optional<Found>& b, const Expr& a_expr, const std::string& b_term,
               const std::string& path, const std::string& what) {
    if (!a || !b) return true;
    if (!a->unit.same_dims(b->unit)) {
      issues.push_back({equation_, path, what + " differ in dimension", described(term(a_expr), *a),
                        described(b_term, *b), true, 1.0});
      return false;
    }
    if (!a->scale_known || !b->scale_known) return true;
    const double ratio = a->unit.scale / b->unit.scale;
    if (std::fabs(ratio - 1.0) < 1e-9) return true;
    const double factor = snapped(std::max(ratio, 1.0 / ratio));
    issues.push_back({equation_, path, what + " differ in scale by a factor of " + significant_digits(factor, 6),
                      described(term(a_expr), *a), described(b_term, *b), false, factor});
    return false;
  }

 private:
  std::optional<Found> apply(const Expr& e) {
    const std::string& op = e.op;
    if (op == "diff") {  // d(x)/d(t): x's units over t's
      const auto x = unit(e.args[0]), t = unit(e.args[1]);
      return times(*x, *t, -1.0);
    }
    if (op == "plus" || op == "minus" || op == "min" || op == "max" || op == "rem") {
      std::vector<const Expr*> all;
      for (const auto& a : e.args) all.push_back(&a);
      return same(all, e.path, "the operands of <" + op + ">");
    }
    if (op == "eq" || op == "neq" || op == "gt" || op == "lt" || op == "geq" || op == "leq") {
      same({&e.args[0], &e.args[1]}, e.path, "the operands of <" + op + ">");
      return Found{};
    }
    if (op == "and" || op == "or" || op == "xor" || op == "not") {
      for (const auto& a : e.args) unit(a);
      return Found{};
    }
    if (op == "times" || op == "divide") {
      std::optional<Found> u;
      bool unknown = false;
      for (std::size_t i = 0; i < e.args.size(); ++i) {
        const auto a = unit(e.args[i]);
        if (!a) unknown = true;
        else if (!u) u = i == 0 ? *a : times(Found{}, *a, op == "divide" ? -1.0 : 1.0);
        else u = times(*u, *a, op == "divide" ? -1.0 : 1.0);
      }
      if (unknown) return std::nullopt;
      return u;
    }
    if (op == "power" || op == "root") {
      const auto base = unit(e.args[0]);
      dimensionless(unit(e.args[1]), e.args[1], "an exponent");
      if (!base) return std::nullopt;
      if (has_variables(e.args[1])) {
        dimensionless(base, e.args[0], "the base of a variable power");
        return base;
      }
      const double exponent = numbers_.eval(e.args[1]);  // a constant expression such as -1
      return raised(*base, op == "power" ? exponent : 1.0 / exponent);
    }
    if (op == "abs" || op == "floor" || op == "ceiling") return unit(e.args[0]);
    // exp, ln, log and the trigonometric functions: dimensionless in and out.
    for (const auto& a : e.args) dimensionless(unit(a), a, "the argument of <" + op + ">");
    return Found{};
  }

  // Operands that must share units: the first known one's, unknown after a
  // difference of dimension, of unknown scale after a difference of scale.
  std::optional<Found> same(const std::vector<const Expr*>& operands, const std::string& path, const std::string& what) {
    std::optional<Found> first;
    const Expr* first_expr = nullptr;
    bool dims_agree = true, scales_agree = true;
    for (const Expr* o : operands) {
      const auto u = unit(*o);
      if (!u) continue;
      if (!first) {
        first = u;
        first_expr = o;
      } else if (!compare(first, u, *first_expr, term(*o), path, what)) {
        (first->unit.same_dims(u->unit) ? scales_agree : dims_agree) = false;
      }
    }
    if (!dims_agree) return std::nullopt;
    if (first && !scales_agree) first->scale_known = false;
    return first;
  }

  void dimensionless(const std::optional<Found>& u, const Expr& e, const std::string& what) {
    if (u && !u->unit.same_dims(Unit{}))
      issues.push_back({equation_, e.path, what + " is not dimensionless", described(term(e), *u), "dimensionless",
                        true, 1.0});
  }

  const Model& m_;
  const Evaluator& numbers_;
  std::string component_;
  std::string equation_;
};

}  // namespace

std::string UnitIssue::text() const {
  return "inconsistent units in " + equation + " at " + path + ": " + what + ": " + first + " against " + second;
}

std::vector<UnitIssue> check_equation_units(const Model& m) {
  std::vector<UnitIssue> all;
  const Evaluator numbers(m);
  for (const auto& eq : m.doc.equations) {
    const auto& lhs_var = m.doc.variables[eq.lhs];
    std::string label = eq.component + "." + lhs_var.name, lhs_term = lhs_var.name;
    Found lhs{lhs_var.unit, lhs_var.units_name, true};
    if (eq.ode) {
      const auto& t = m.doc.variables[eq.bvar];
      lhs = times(lhs, Found{t.unit, t.units_name, true}, -1.0);
      lhs_term = "d(" + lhs_var.name + ")/d(" + t.name + ")";
      label = eq.component + "." + lhs_term;
    }
    Checker c(m, numbers, eq.component, label);
    const auto rhs = c.unit(eq.rhs);
    Expr lhs_expr;
    lhs_expr.kind = Expr::Kind::variable;
    lhs_expr.name = lhs_term;
    c.compare(lhs, rhs, lhs_expr, term(eq.rhs), eq.path, "the two sides of the equation");
    all.insert(all.end(), c.issues.begin(), c.issues.end());
  }
  return all;
}

}  // namespace fibrodem::cellml
