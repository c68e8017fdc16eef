// Gate recognition: a state whose rate has the linear form of a gate,
// (inf - x) / tau or alpha (1 - x) - beta x, is integrated by Rush-Larsen
// (Rush & Larsen, IEEE TBME 25:389, 1978) from its a and b in dy/dt = a + b y.
#pragma once

#include <vector>

#include "cellml/interface_map.hpp"
#include "cellml/model_analysis.hpp"

namespace fibrodem::cellml {

struct GateForm {
  enum class Form { none, inf_tau, alpha_beta } form = Form::none;
  const Expr* first = nullptr;   // inf or alpha
  const Expr* second = nullptr;  // tau or beta
  bool gate = false;             // in [0, 1]: Rush-Larsen's gate
  bool voltage_only = false;
};

// Expression shapes.
inline bool is_one(const Expr& e) { return e.kind == Expr::Kind::number && e.value == 1.0; }
inline bool is_op(const Expr& e, const char* op, std::size_t n) {
  return e.kind == Expr::Kind::apply && e.op == op && e.args.size() == n;
}

// The form of state q's rate; `timed` marks quantities that change with time
// by themselves (they make a gate not voltage_only).
GateForm recognise_gate(const Model& model, const InterfaceMap& boundary, const std::vector<bool>& timed, int q);

}  // namespace fibrodem::cellml
