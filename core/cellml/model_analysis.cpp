#include "cellml/model_analysis.hpp"

#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>

#include "cellml/import_error.hpp"
#include "util/number_text.hpp"

namespace fibrodem::cellml {

namespace {

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

bool is_derivative(const Expr& e) { return e.kind == Expr::Kind::apply && e.op == "diff"; }

// A derivative d(x)/d(t) inside an expression uses x and whatever x's rate
// uses, since it is evaluated as that rate (check_derivatives() has made
// sure x is a state and that no rate reads itself).
void collect_uses(const Model& m, const Expr& e, std::vector<int>& out) {
  if (e.kind == Expr::Kind::variable) out.push_back(m.quantity_of[e.var]);
  if (is_derivative(e)) {
    const auto& q = m.quantities[m.quantity_of[e.args[0].var]];
    out.push_back(m.quantity_of[e.args[0].var]);
    collect_uses(m, m.doc.equations[q.equation].rhs, out);
    return;
  }
  for (const auto& a : e.args) collect_uses(m, a, out);
}

// Every d(x)/d(t) on a right side: x a state, t the independent variable, and
// no chain of such derivatives that leads back to the rate it started from.
void check_derivatives(const Model& m, const Expr& e, std::vector<int>& chain) {
  if (is_derivative(e)) {
    const auto& x = m.doc.variables[e.args[0].var];
    const int q = m.quantity_of[e.args[0].var];
    if (m.quantities[q].role != Role::state)
      throw ImportError(e.path + ": d(" + x.name + ")/d(" + e.args[1].name + ") on a right side: " + x.qualified() +
                        " is not a state (only the rate of a state, from its own equation, can be used)");
    if (m.quantity_of[e.args[1].var] != m.time)
      throw ImportError(e.path + ": d(" + x.name + ")/d(" + e.args[1].name + "): " +
                        m.doc.variables[e.args[1].var].qualified() + " is not the independent variable " +
                        m.source(m.time).qualified());
    for (int c : chain)
      if (c == q)
        throw ImportError(e.path + ": the rate of " + x.qualified() +
                          " is defined through its own derivative (an implicit equation)");
    chain.push_back(q);
    check_derivatives(m, m.doc.equations[m.quantities[q].equation].rhs, chain);
    chain.pop_back();
    return;
  }
  for (const auto& a : e.args) check_derivatives(m, a, chain);
}

std::optional<double> as_number(const std::string& s) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// Kahn's algorithm over the algebraic quantities; what is left is a loop.
void order_equations(Model& m) {
  const int n = static_cast<int>(m.quantities.size());
  std::vector<int> pending(n, 0);
  std::vector<std::vector<int>> users(n);
  for (int q = 0; q < n; ++q) {
    if (m.quantities[q].role != Role::algebraic) continue;
    for (int u : m.quantities[q].uses)
      if (m.quantities[u].role == Role::algebraic) {
        ++pending[q];
        users[u].push_back(q);
      }
  }
  std::vector<int> ready;
  for (int q = 0; q < n; ++q)
    if (m.quantities[q].role == Role::algebraic && pending[q] == 0) ready.push_back(q);
  for (std::size_t i = 0; i < ready.size(); ++i) {
    m.order.push_back(ready[i]);
    for (int u : users[ready[i]])
      if (--pending[u] == 0) ready.push_back(u);
  }
  for (int q = 0; q < n; ++q) {
    if (m.quantities[q].role != Role::algebraic || pending[q] == 0) continue;
    // Walk back along unresolved uses until a quantity repeats: that is the loop.
    std::vector<int> walk{q};
    std::vector<int> seen(n, -1);
    seen[q] = 0;
    for (;;) {
      int next = -1;
      for (int u : m.quantities[walk.back()].uses)
        if (m.quantities[u].role == Role::algebraic && pending[u] > 0) {
          next = u;
          break;
        }
      if (next < 0 || seen[next] >= 0) {
        std::string names;
        for (std::size_t k = next < 0 ? 0 : seen[next]; k < walk.size(); ++k)
          names += m.source(walk[k]).qualified() + " -> ";
        names += next < 0 ? "?" : m.source(next).qualified();
        throw ImportError(m.doc.equations[m.quantities[walk.back()].equation].path +
                          ": algebraic loop (the equations cannot be ordered; a DAE or an implicit "
                          "system is not supported): " + names);
      }
      seen[next] = static_cast<int>(walk.size());
      walk.push_back(next);
    }
  }
}

}  // namespace

double snapped(double x) {
  return std::strtod(significant_digits(x, 15).c_str(), nullptr);
}

double Model::factor_to(int v) const {
  const auto& src = source(quantity_of[v]);
  return snapped(src.unit.scale / doc.variables[v].unit.scale);
}

double Model::rate_factor(int q) const {
  const auto& eq = doc.equations[quantities[q].equation];
  // d(x_src)/d(t_src) = d(x_lhs)/d(t_bvar) * (x_lhs/x_src) / (t_bvar/t_src)
  return snapped((doc.variables[eq.lhs].unit.scale / source(q).unit.scale) /
                 (doc.variables[eq.bvar].unit.scale / source(time).unit.scale));
}

Model analyse(Document doc) {
  Model m;
  m.doc = std::move(doc);
  const auto& vars = m.doc.variables;
  const int nv = static_cast<int>(vars.size());
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& c : m.doc.connections) {
    if (!vars[c.a].unit.same_dims(vars[c.b].unit))
      throw ImportError(c.path + ": inconsistent units: " + vars[c.a].qualified() + " [" + vars[c.a].units_name +
                        " = " + vars[c.a].unit.dims_text() + "] connected to " + vars[c.b].qualified() + " [" +
                        vars[c.b].units_name + " = " + vars[c.b].unit.dims_text() + "]");
    parent[find_root(parent, c.a)] = find_root(parent, c.b);
  }
  m.quantity_of.assign(nv, -1);
  for (int v = 0; v < nv; ++v) {
    const int r = find_root(parent, v);
    if (m.quantity_of[r] < 0) {
      m.quantity_of[r] = static_cast<int>(m.quantities.size());
      m.quantities.emplace_back();
    }
    m.quantity_of[v] = m.quantity_of[r];
    m.quantities[m.quantity_of[v]].members.push_back(v);
  }
  // Definitions: equations, then initial values.
  int time_var = -1;
  for (int e = 0; e < static_cast<int>(m.doc.equations.size()); ++e) {
    const auto& eq = m.doc.equations[e];
    auto& q = m.quantities[m.quantity_of[eq.lhs]];
    if (q.equation >= 0)
      throw ImportError(eq.path + ": " + vars[eq.lhs].qualified() + " is defined twice (also at " +
                        m.doc.equations[q.equation].path + ")");
    q.equation = e;
    q.source = eq.lhs;
    q.role = eq.ode ? Role::state : Role::algebraic;
    if (eq.ode) {
      if (time_var >= 0 && m.quantity_of[time_var] != m.quantity_of[eq.bvar])
        throw ImportError(eq.path + ": derivative with respect to " + vars[eq.bvar].qualified() + ", not " +
                          vars[time_var].qualified() + " (one independent variable only)");
      time_var = eq.bvar;
    }
  }
  if (time_var < 0) throw ImportError(m.doc.file + ": the model has no differential equation");
  m.time = m.quantity_of[time_var];
  for (int qi = 0; qi < static_cast<int>(m.quantities.size()); ++qi) {
    auto& q = m.quantities[qi];
    int initial_var = -1;
    for (int v : q.members)
      if (!vars[v].initial.empty()) {
        if (initial_var >= 0)
          throw ImportError(vars[v].path + ": a second initial value for " + vars[v].qualified() +
                            " (connected to " + vars[initial_var].qualified() + ", which has one)");
        initial_var = v;
      }
    if (qi == m.time) {
      if (q.equation >= 0 || initial_var >= 0)
        throw ImportError(vars[time_var].path + ": the independent variable " + vars[time_var].qualified() +
                          " must not have an equation or an initial value");
      q.role = Role::time;
      q.source = time_var;
      continue;
    }
    if (q.role == Role::algebraic && q.equation >= 0 && initial_var >= 0)
      throw ImportError(vars[initial_var].path + ": " + vars[initial_var].qualified() +
                        " has both an initial value and an algebraic equation (" +
                        m.doc.equations[q.equation].path + ")");
    if (q.equation < 0) {
      if (initial_var < 0)
        throw ImportError(vars[q.members[0]].path + ": " + vars[q.members[0]].qualified() +
                          " has no value (no equation, no initial_value)");
      q.role = Role::parameter;
      q.source = initial_var;
    } else if (q.role == Role::state && initial_var < 0) {
      throw ImportError(vars[q.source].path + ": state " + vars[q.source].qualified() + " has no initial_value");
    }
  }
  // Initial values: numbers, or (1.1, 2.0) the name of a constant in the same component.
  for (int qi = 0; qi < static_cast<int>(m.quantities.size()); ++qi) {
    auto& q = m.quantities[qi];
    if (q.role != Role::state && q.role != Role::parameter) continue;
    int initial_var = -1;
    for (int v : q.members)
      if (!vars[v].initial.empty()) initial_var = v;
    const auto& iv = vars[initial_var];
    const double to_source = iv.unit.scale / m.source(qi).unit.scale;
    if (const auto number = as_number(iv.initial)) {
      q.initial = *number * to_source;
    } else {
      const int ref = m.doc.find(iv.component, iv.initial);
      if (ref < 0 || m.quantities[m.quantity_of[ref]].role != Role::parameter ||
          m.quantity_of[ref] == qi)
        throw ImportError(iv.path + ": initial_value '" + iv.initial +
                          "' is neither a number nor a constant of component '" + iv.component + "'");
      const auto& rq = m.quantities[m.quantity_of[ref]];
      const auto& rv = vars[rq.source];
      if (!as_number(rv.initial))
        throw ImportError(iv.path + ": initial_value '" + iv.initial + "' refers to another reference");
      if (rv.unit.same_dims(iv.unit)) {
        q.initial = *as_number(rv.initial) * (rv.unit.scale / iv.unit.scale) * to_source;
      } else {  // no conversion between dimensions: the number as written, and a warning
        m.initial_value_unit_issues.push_back(
            "inconsistent units in the initial value of " + iv.qualified() + " at " + iv.path + ": it names '" +
            iv.initial + "' [" + rv.unit.described_as(rv.units_name) + "], of another dimension than " +
            iv.qualified() + " [" + iv.unit.described_as(iv.units_name) + "]; its number is taken as written");
        q.initial = *as_number(rv.initial) * to_source;
      }
    }
  }
  for (int qi = 0; qi < static_cast<int>(m.quantities.size()); ++qi) {
    const auto& q = m.quantities[qi];
    std::vector<int> chain;
    if (q.role == Role::state) chain.push_back(qi);
    if (q.equation >= 0) check_derivatives(m, m.doc.equations[q.equation].rhs, chain);
  }
  for (int qi = 0; qi < static_cast<int>(m.quantities.size()); ++qi) {
    auto& q = m.quantities[qi];
    if (q.equation >= 0) collect_uses(m, m.doc.equations[q.equation].rhs, q.uses);
    if (q.role == Role::state) m.states.push_back(qi);
    if (q.role == Role::parameter) m.parameters.push_back(qi);
    if (q.role == Role::algebraic)
      for (int u : q.uses)
        if (u == qi)
          throw ImportError(m.doc.equations[q.equation].path + ": " + m.source(qi).qualified() +
                            " is defined in terms of itself (an implicit equation)");
  }
  order_equations(m);
  return m;
}

std::vector<bool> dependencies(const Model& m, const Expr& e) {
  std::vector<bool> seen(m.quantities.size(), false);
  std::vector<int> stack;
  collect_uses(m, e, stack);
  while (!stack.empty()) {
    const int q = stack.back();
    stack.pop_back();
    if (seen[q]) continue;
    seen[q] = true;
    if (m.quantities[q].role == Role::algebraic)
      for (int u : m.quantities[q].uses) stack.push_back(u);
  }
  return seen;
}

// ---- numbers -------------------------------------------------------------------

Evaluator::Evaluator(const Model& model) : m_(model) {
  values.assign(model.quantities.size(), 0.0);
  for (std::size_t q = 0; q < model.quantities.size(); ++q)
    if (model.quantities[q].role == Role::state || model.quantities[q].role == Role::parameter)
      values[q] = model.quantities[q].initial;
  update();
}

void Evaluator::update() {
  for (int q : m_.order) {
    if (!pinned.empty() && pinned[q]) continue;
    const auto& eq = m_.doc.equations[m_.quantities[q].equation];
    values[q] = eval(eq.rhs) / m_.factor_to(eq.lhs);
  }
}

double Evaluator::rate(int q) const {
  return eval(m_.doc.equations[m_.quantities[q].equation].rhs) * m_.rate_factor(q);
}

double Evaluator::eval(const Expr& e) const {
  const auto& a = e.args;
  auto arg = [&](std::size_t i) { return eval(a[i]); };
  switch (e.kind) {
    case Expr::Kind::number: return e.value;
    case Expr::Kind::variable: return values[m_.quantity_of[e.var]] * m_.factor_to(e.var);
    case Expr::Kind::constant:
      if (e.op == "pi") return M_PI;
      if (e.op == "exponentiale") return M_E;
      if (e.op == "true") return 1.0;
      if (e.op == "false") return 0.0;
      if (e.op == "infinity") return std::numeric_limits<double>::infinity();
      return std::numeric_limits<double>::quiet_NaN();
    case Expr::Kind::piecewise: {
      const std::size_t pieces = (a.size() - (e.has_otherwise ? 1 : 0)) / 2;
      for (std::size_t i = 0; i < pieces; ++i)
        if (arg(2 * i + 1) != 0.0) return arg(2 * i);
      return e.has_otherwise ? arg(a.size() - 1) : std::numeric_limits<double>::quiet_NaN();
    }
    case Expr::Kind::apply: break;
  }
  const std::string& op = e.op;
  if (op == "diff") {  // d(x)/d(t) in x's and t's own units
    const int x = e.args[0].var, t = e.args[1].var;
    return rate(m_.quantity_of[x]) * m_.factor_to(x) / m_.factor_to(t);
  }
  if (op == "plus") {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += arg(i);
    return s;
  }
  if (op == "minus") return a.size() == 1 ? -arg(0) : arg(0) - arg(1);
  if (op == "times") {
    double s = 1;
    for (std::size_t i = 0; i < a.size(); ++i) s *= arg(i);
    return s;
  }
  if (op == "divide") return arg(0) / arg(1);
  if (op == "power") return std::pow(arg(0), arg(1));
  if (op == "root") return arg(1) == 2.0 ? std::sqrt(arg(0)) : std::pow(arg(0), 1.0 / arg(1));
  if (op == "exp") return std::exp(arg(0));
  if (op == "ln") return std::log(arg(0));
  if (op == "log") return std::log(arg(0)) / std::log(arg(1));
  if (op == "abs") return std::fabs(arg(0));
  if (op == "floor") return std::floor(arg(0));
  if (op == "ceiling") return std::ceil(arg(0));
  if (op == "rem") return std::fmod(arg(0), arg(1));
  if (op == "min" || op == "max") {
    double s = arg(0);
    for (std::size_t i = 1; i < a.size(); ++i) s = op == "min" ? std::fmin(s, arg(i)) : std::fmax(s, arg(i));
    return s;
  }
  if (op == "eq") return arg(0) == arg(1);
  if (op == "neq") return arg(0) != arg(1);
  if (op == "gt") return arg(0) > arg(1);
  if (op == "lt") return arg(0) < arg(1);
  if (op == "geq") return arg(0) >= arg(1);
  if (op == "leq") return arg(0) <= arg(1);
  if (op == "and" || op == "or" || op == "xor") {
    bool s = arg(0) != 0.0;
    for (std::size_t i = 1; i < a.size(); ++i) {
      const bool b = arg(i) != 0.0;
      s = op == "and" ? (s && b) : op == "or" ? (s || b) : (s != b);
    }
    return s;
  }
  if (op == "not") return arg(0) == 0.0;
  const double x = arg(0);
  if (op == "sin") return std::sin(x);
  if (op == "cos") return std::cos(x);
  if (op == "tan") return std::tan(x);
  if (op == "sec") return 1 / std::cos(x);
  if (op == "csc") return 1 / std::sin(x);
  if (op == "cot") return 1 / std::tan(x);
  if (op == "sinh") return std::sinh(x);
  if (op == "cosh") return std::cosh(x);
  if (op == "tanh") return std::tanh(x);
  if (op == "sech") return 1 / std::cosh(x);
  if (op == "csch") return 1 / std::sinh(x);
  if (op == "coth") return 1 / std::tanh(x);
  if (op == "arcsin") return std::asin(x);
  if (op == "arccos") return std::acos(x);
  if (op == "arctan") return std::atan(x);
  if (op == "arcsec") return std::acos(1 / x);
  if (op == "arccsc") return std::asin(1 / x);
  if (op == "arccot") return std::atan(1 / x);
  if (op == "arcsinh") return std::asinh(x);
  if (op == "arccosh") return std::acosh(x);
  if (op == "arctanh") return std::atanh(x);
  if (op == "arcsech") return std::acosh(1 / x);
  if (op == "arccsch") return std::asinh(1 / x);
  if (op == "arccoth") return std::atanh(1 / x);
  throw ImportError(e.path + ": unsupported MathML element <" + op + ">");
}

}  // namespace fibrodem::cellml
