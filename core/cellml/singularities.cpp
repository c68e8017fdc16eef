#include "cellml/singularities.hpp"

#include <cmath>

#include "cellml/gate_form.hpp"

namespace fibrodem::cellml {

// d(e)/dV as code, for expressions affine in V (nullopt: not handled; "" : zero).
std::optional<std::string> Singularities::derivative(const Expr& e) {
  const int v = b_.v;
  const bool depends = (e.kind == Expr::Kind::variable && m_.quantity_of[e.var] == v) || dependencies(m_, e)[v];
  if (!depends) return std::string();
  if (e.kind == Expr::Kind::variable) {
    const int q = m_.quantity_of[e.var];
    if (q == v) return lit(m_.factor_to(e.var));
    if (m_.quantities[q].role != Role::algebraic || q == b_.stim) return std::nullopt;
    const auto& eq = m_.doc.equations[m_.quantities[q].equation];
    auto d = derivative(eq.rhs);
    if (!d || d->empty()) return d;
    const double f = m_.factor_to(e.var) / m_.factor_to(eq.lhs);
    return f == 1.0 ? *d : "(" + *d + " * " + lit(f) + ")";
  }
  if (e.kind != Expr::Kind::apply) return std::nullopt;
  if (e.op == "plus" || e.op == "minus") {
    std::string s;
    for (std::size_t i = 0; i < e.args.size(); ++i) {
      auto d = derivative(e.args[i]);
      if (!d) return std::nullopt;
      if (d->empty()) continue;
      const bool negative = e.op == "minus" && (i == 1 || e.args.size() == 1);
      s += (negative ? " - " : (s.empty() ? "" : " + ")) + *d;
    }
    return s.empty() ? s : "(" + s + ")";
  }
  if (e.op == "times") {
    int which = -1;
    std::string d_which;
    for (std::size_t i = 0; i < e.args.size(); ++i) {
      auto d = derivative(e.args[i]);
      if (!d) return std::nullopt;
      if (d->empty()) continue;
      if (which >= 0) return std::nullopt;  // not affine
      which = static_cast<int>(i);
      d_which = *d;
    }
    std::string s = d_which;
    for (std::size_t i = 0; i < e.args.size(); ++i)
      if (static_cast<int>(i) != which) s += " * " + w_.emit(e.args[i]).text;
    return "(" + s + ")";
  }
  if (e.op == "divide") {
    auto dd = derivative(e.args[1]);
    if (!dd || !dd->empty()) return std::nullopt;
    auto dn = derivative(e.args[0]);
    if (!dn) return std::nullopt;
    return "(" + *dn + " / " + w_.emit(e.args[1]).text + ")";
  }
  return std::nullopt;
}

// The values of an expression as V sweeps the physiological range (others at
// their initial values).
std::vector<double> Singularities::sweep_V(const Expr& e) const {
  std::vector<double> out;
  Evaluator ev(m_);
  for (double v_mV : {-95.0, -60.0, -31.0, -7.0, 18.0, 47.0}) {
    ev.values[b_.v] = v_mV / b_.v_scale;
    ev.update();
    out.push_back(ev.eval(e));
  }
  return out;
}

std::optional<Code> Singularities::rewrite(const Expr& e) {
  if (b_.v < 0) return std::nullopt;
  const Expr& d = e.args[1];
  if (!is_op(d, "minus", 2)) return std::nullopt;
  const Expr* exponent = nullptr;
  bool one_minus = false;
  if (is_op(d.args[0], "exp", 1) && is_one(d.args[1])) exponent = &d.args[0].args[0];
  if (is_one(d.args[0]) && is_op(d.args[1], "exp", 1)) {
    exponent = &d.args[1].args[0];
    one_minus = true;
  }
  if (!exponent) return std::nullopt;
  const auto E = sweep_V(*exponent);
  if (std::fabs(E.front() - E.back()) < 1e-12) return std::nullopt;  // not a function of V
  std::vector<const Expr*> factors;
  const Expr& n = e.args[0];
  if (is_op(n, "times", n.args.size()) && n.args.size() > 1)
    for (const auto& f : n.args) factors.push_back(&f);
  factors.insert(factors.begin(), &n);
  for (const Expr* f : factors) {
    const auto N = sweep_V(*f);
    bool proportional = true;
    const double r0 = N[0] / E[0];
    for (std::size_t i = 0; i < N.size(); ++i)
      if (!std::isfinite(N[i] / E[i]) || std::fabs(N[i] / E[i] - r0) > 1e-9 * std::fabs(r0) + 1e-300)
        proportional = false;
    if (!proportional || r0 == 0.0) continue;
    const auto dN = derivative(*f), dE = derivative(*exponent);
    if (!dN || !dE || dN->empty() || dE->empty()) continue;
    std::string rest;
    if (f != &n)
      for (const auto& g : n.args)
        if (&g != f) rest += w_.emit(g).text + " * ";
    const Code x = w_.emit(*exponent);
    std::string text = "(" + rest + (one_minus ? "(-" : "(") + *dN + " / " + *dE + ") * exprel(" +
                       (x.lane ? "" : "double") + "(-" + x.text + ")))";
    paths_.push_back(e.path);
    return Code{text, w_.emit(n).lane || x.lane, false};
  }
  return std::nullopt;
}

}  // namespace fibrodem::cellml
