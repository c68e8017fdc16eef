#include "cellml/expression_writer.hpp"

#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include "cellml/import_error.hpp"

namespace fibrodem::cellml {

namespace {

const std::set<std::string>& reserved() {
  static const std::set<std::string> words = {
      "R", "cell", "block", "p", "t_ms", "time", "exp", "expm1", "log", "pow", "sqrt", "fabs", "fmin", "fmax",
      "floor", "select", "exprel", "std", "fibrodem", "alignas", "alignof", "and", "and_eq", "asm", "auto",
      "bitand", "bitor", "bool", "break", "case", "catch", "char", "class", "compl", "const", "constexpr",
      "const_cast", "continue", "decltype", "default", "delete", "do", "double", "dynamic_cast", "else", "enum",
      "explicit", "export", "extern", "false", "float", "for", "friend", "goto", "if", "inline", "int", "long",
      "mutable", "namespace", "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq",
      "private", "protected", "public", "register", "reinterpret_cast", "return", "short", "signed", "sizeof",
      "static", "static_assert", "static_cast", "struct", "switch", "template", "this", "throw", "true", "try",
      "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void", "volatile", "wchar_t",
      "while", "xor", "xor_eq", "C_pF", "dV_dt", "M_PI", "M_E", "NAN", "INFINITY", "main", "info_", "Model"};
  return words;
}

}  // namespace

std::string sanitize(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "x_" + out;
  return out;
}

std::vector<std::string> identifiers(const Model& m, int v) {
  const int n = static_cast<int>(m.quantities.size());
  std::vector<std::string> ident(n);
  std::map<std::string, int> count;
  for (int q = 0; q < n; ++q) ++count[sanitize(m.source(q).name)];
  std::set<std::string> taken;
  for (int q = 0; q < n; ++q) {
    const auto& s = m.source(q);
    std::string id = sanitize(s.name);
    if (q == v) id = "V";  // fibrodem's name for the membrane potential
    else if (count[id] > 1 || reserved().count(id) || (v >= 0 && id == "V")) id = sanitize(s.component + "_" + s.name);
    while (taken.count(id) || reserved().count(id)) id += "_";
    taken.insert(id);
    ident[q] = id;
  }
  ident[m.time] = "time";
  return ident;
}

Code ExpressionWriter::variable(int v) const {
  const int q = m_.quantity_of[v];
  const double f = m_.factor_to(v);
  std::string text = ident_[q];
  if (f != 1.0) text = "(" + text + " * " + lit(f) + ")";
  return {text, lane_[q], false};
}

Code ExpressionWriter::emit(const Expr& e) {
  switch (e.kind) {
    case Expr::Kind::number: return {lit(e.value), false, false};
    case Expr::Kind::variable: return variable(e.var);
    case Expr::Kind::constant:
      if (e.op == "pi") return {lit(M_PI), false, false};
      if (e.op == "exponentiale") return {lit(M_E), false, false};
      if (e.op == "true" || e.op == "false") return {e.op, false, true};
      if (e.op == "infinity") return {lit(INFINITY), false, false};
      return {lit(NAN), false, false};
    case Expr::Kind::piecewise: return piecewise(e);
    case Expr::Kind::apply: break;
  }
  if (e.op == "diff") return derivative(e);
  if (e.op == "divide" && rewrite_divide)
    if (auto rewritten = rewrite_divide(e)) return *rewritten;
  std::vector<Code> a;
  bool lane = false;
  for (const auto& x : e.args) {
    a.push_back(emit(x));
    lane = lane || a.back().lane;
  }
  const std::string& op = e.op;
  auto join = [&](const char* sep) {
    std::string s = "(";
    for (std::size_t i = 0; i < a.size(); ++i) s += (i ? sep : "") + a[i].text;
    return Code{s + ")", lane, false};
  };
  auto call = [&](const std::string& f) { return Code{f + "(" + a[0].text + ")", lane, false}; };
  auto both = [&](std::size_t i) { return lane ? as_lane(a[i]) : a[i].text; };
  if (op == "plus") return join(" + ");
  if (op == "times") return join(" * ");
  if (op == "minus") return a.size() == 1 ? Code{"(-" + a[0].text + ")", lane, false} : join(" - ");
  if (op == "divide") return join(" / ");
  if (op == "power") {
    if (e.args[1].kind == Expr::Kind::number && e.args[1].value == 2.0)
      return {"square(" + a[0].text + ")", lane, false};
    return {"pow(" + a[0].text + ", " + a[1].text + ")", lane, false};
  }
  if (op == "root") {
    if (e.args[1].kind == Expr::Kind::number && e.args[1].value == 2.0) return call("sqrt");
    return {"pow(" + a[0].text + ", 1.0 / " + a[1].text + ")", lane, false};
  }
  if (op == "exp") return call("exp");
  if (op == "ln") return call("log");
  if (op == "log") return {"(log(" + a[0].text + ") / log(" + a[1].text + "))", lane, false};
  if (op == "abs") return call("fabs");
  if (op == "floor") return call("floor");
  if (op == "ceiling") return {"(-floor(-" + a[0].text + "))", lane, false};
  if (op == "rem") return {"cm_rem(" + both(0) + ", " + both(1) + ")", lane, false};
  if (op == "min" || op == "max") {
    std::string s = both(0);
    for (std::size_t i = 1; i < a.size(); ++i) s = std::string(op == "min" ? "fmin(" : "fmax(") + s + ", " + both(i) + ")";
    return {s, lane, false};
  }
  static const std::map<std::string, std::string> relations = {
      {"eq", " == "}, {"neq", " != "}, {"gt", " > "}, {"lt", " < "}, {"geq", " >= "}, {"leq", " <= "}};
  if (const auto r = relations.find(op); r != relations.end())
    return {"(" + both(0) + r->second + both(1) + ")", lane, true};  // xsimd has no double < lanes
  if (op == "and" || op == "or" || op == "xor" || op == "not") {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!a[i].boolean) a[i].text = "(" + a[i].text + " != 0.0)";
    if (lane)
      for (auto& x : a) x.text = as_mask(x);
    if (op == "not") return {"(!" + a[0].text + ")", lane, true};
    Code c = join(op == "and" ? " && " : op == "or" ? " || " : " != ");
    c.boolean = true;
    return c;
  }
  return {"cm_" + op + "(" + a[0].text + ")", lane, false};  // trigonometric and hyperbolic (cellml_math.hpp)
}

// d(x)/d(t) on a right side: x's own rate expression, in x's and t's units
// (the writer emits it again where it is used rather than reading the rate,
// which is computed after the algebraic quantities).
Code ExpressionWriter::derivative(const Expr& e) {
  const int x = e.args[0].var, t = e.args[1].var, q = m_.quantity_of[x];
  if (q == b_.v && b_.stim < 0)
    throw ImportError(e.path + ": d(" + e.args[0].name + ")/d(" + e.args[1].name +
                      ") of the membrane potential on a right side, in a model without a stimulus variable "
                      "(fibrodem adds i_ext to dV/dt itself there; name one with --stimulus)");
  const Code rate = emit(m_.doc.equations[m_.quantities[q].equation].rhs);
  const double f = snapped(m_.rate_factor(q) * m_.factor_to(x) / m_.factor_to(t));
  if (f == 1.0) return {"(" + rate.text + ")", rate.lane, false};
  return {"(" + rate.text + " * " + lit(f) + ")", rate.lane, false};
}

Code ExpressionWriter::piecewise(const Expr& e) {
  const std::size_t pieces = (e.args.size() - (e.has_otherwise ? 1 : 0)) / 2;
  std::vector<Code> values, conditions;
  bool lane = false;
  for (std::size_t i = 0; i < pieces; ++i) {
    values.push_back(emit(e.args[2 * i]));
    conditions.push_back(emit(e.args[2 * i + 1]));
    if (!conditions.back().boolean) conditions.back().text = "(" + conditions.back().text + " != 0.0)";
    lane = lane || values.back().lane || conditions.back().lane;
  }
  Code acc = e.has_otherwise ? emit(e.args.back()) : Code{lit(NAN), false, false};
  lane = lane || acc.lane;
  for (std::size_t k = pieces; k-- > 0;) {
    if (!lane) acc.text = "(" + conditions[k].text + " ? " + values[k].text + " : " + acc.text + ")";
    else if (conditions[k].lane)
      acc.text = "select(" + conditions[k].text + ", " + as_lane(values[k]) + ", " + as_lane(acc) + ")";
    else
      acc.text = "(" + conditions[k].text + " ? " + as_lane(values[k]) + " : " + as_lane(acc) + ")";
    acc.lane = lane;
  }
  return acc;
}

}  // namespace fibrodem::cellml
