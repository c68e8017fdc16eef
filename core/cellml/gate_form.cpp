#include "cellml/gate_form.hpp"

namespace fibrodem::cellml {

namespace {

bool is_state_ref(const Model& m, const Expr& e, int q) {
  return e.kind == Expr::Kind::variable && m.quantity_of[e.var] == q && m.factor_to(e.var) == 1.0;
}

bool free_of(const Model& m, const Expr& e, int q) { return !dependencies(m, e)[q]; }

}  // namespace

GateForm recognise_gate(const Model& m, const InterfaceMap& boundary, const std::vector<bool>& timed, int q) {
  const Expr& rhs = m.doc.equations[m.quantities[q].equation].rhs;
  GateForm g;
  // (inf - x) / tau
  if (is_op(rhs, "divide", 2) && is_op(rhs.args[0], "minus", 2) && is_state_ref(m, rhs.args[0].args[1], q) &&
      free_of(m, rhs.args[0].args[0], q) && free_of(m, rhs.args[1], q)) {
    g.form = GateForm::Form::inf_tau;
    g.first = &rhs.args[0].args[0];
    g.second = &rhs.args[1];
  }
  // alpha (1 - x) - beta x, either order of the factors
  if (is_op(rhs, "minus", 2) && is_op(rhs.args[0], "times", 2) && is_op(rhs.args[1], "times", 2)) {
    const Expr* alpha = nullptr;
    const Expr* beta = nullptr;
    for (int i = 0; i < 2; ++i) {
      const Expr& f = rhs.args[0].args[i];
      if (is_op(f, "minus", 2) && is_one(f.args[0]) && is_state_ref(m, f.args[1], q)) alpha = &rhs.args[0].args[1 - i];
      if (is_state_ref(m, rhs.args[1].args[i], q)) beta = &rhs.args[1].args[1 - i];
    }
    if (alpha && beta && free_of(m, *alpha, q) && free_of(m, *beta, q)) {
      g.form = GateForm::Form::alpha_beta;
      g.first = alpha;
      g.second = beta;
    }
  }
  if (g.form == GateForm::Form::none) return g;
  const auto& s = m.source(q);
  g.gate = s.unit.dims.empty() && s.unit.scale == 1.0 && m.quantities[q].initial >= 0.0 &&
           m.quantities[q].initial <= 1.0;
  std::vector<bool> deps = dependencies(m, *g.first);
  const auto more = dependencies(m, *g.second);
  for (std::size_t k = 0; k < deps.size(); ++k) deps[k] = deps[k] || more[k];
  // voltage_only: a, b depend on V and constants alone (through any algebraic chain).
  g.voltage_only = g.gate;
  for (std::size_t k = 0; k < deps.size(); ++k)
    if (deps[k] && (timed[k] || static_cast<int>(k) == boundary.ca_input || static_cast<int>(k) == boundary.stim ||
                    (m.quantities[k].role == Role::state && static_cast<int>(k) != boundary.v)))
      g.voltage_only = false;
  return g;
}

}  // namespace fibrodem::cellml
