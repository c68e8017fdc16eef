#include "cellml/plugin_writer.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <set>
#include <sstream>

#include "cellml/import_error.hpp"

namespace fibrodem::cellml {

namespace {

// A number as a C++ double literal that reads back to the same value.
std::string lit(double x) {
  if (std::isnan(x)) return "std::numeric_limits<double>::quiet_NaN()";
  if (std::isinf(x)) return x > 0 ? "std::numeric_limits<double>::infinity()" : "(-std::numeric_limits<double>::infinity())";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  for (int digits = 6; digits < 17; ++digits) {  // the shortest that round-trips
    char shorter[40];
    std::snprintf(shorter, sizeof shorter, "%.*g", digits, x);
    if (std::strtod(shorter, nullptr) == x) {
      std::snprintf(buf, sizeof buf, "%s", shorter);
      break;
    }
  }
  std::string s = buf;
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return x < 0 ? "(" + s + ")" : s;
}

struct Code {
  std::string text;
  bool lane = false;     // depends on a cell's state or input: lanes of R
  bool boolean = false;  // a condition
};

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
      "while", "xor", "xor_eq", "C_pF", "M_PI", "M_E", "NAN", "INFINITY", "main", "info_", "Model"};
  return words;
}

std::string sanitize(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "x_" + out;
  return out;
}

class Writer {
 public:
  Writer(const Model& m, const WriterOptions& o) : m_(m), o_(o) {}

  GeneratedPlugin run() {
    find_boundary();
    classify();
    name_quantities();
    GeneratedPlugin out;
    out.cpp = source();
    out.cmake = cmake();
    out.notes = notes_;
    return out;
  }

 private:
  // ---- what the model is at fibrodem's boundary ---------------------------------

  int quantity_named(const std::string& qualified, const std::string& what) const {
    const auto dot = qualified.find('.');
    const int v = dot == std::string::npos ? -1 : m_.doc.find(qualified.substr(0, dot), qualified.substr(dot + 1));
    if (v < 0)
      throw ImportError(what + " '" + qualified + "': no such variable (expected component.variable)");
    return m_.quantity_of[v];
  }

  void find_boundary() {
    const auto& time_unit = m_.source(m_.time);
    if (!time_unit.unit.same_dims(second_unit()))
      throw ImportError(time_unit.path + ": the independent variable " + time_unit.qualified() + " is in '" +
                        time_unit.units_name + "' (" + time_unit.unit.dims_text() + "), not a time");
    // t_src = t_ms * time_scale_
    time_scale_ = 1e-3 / time_unit.unit.scale;
    if (time_scale_ != 1.0)
      notes_.push_back("time: the CellML's " + time_unit.qualified() + " is in " + time_unit.units_name +
                       "; time = t_ms * " + lit(time_scale_) + ", rates * " + lit(time_scale_) + " per ms");
    for (const auto& [signal, target] : o_.map) mapped_[signal] = quantity_named(target, "--map " + signal);
    if (o_.myofilament) {
      if (!mapped_.count("Ca_i")) throw ImportError("a myofilament model needs --map Ca_i=component.variable (its input)");
      if (!mapped_.count("sarcomere_length"))
        throw ImportError("a myofilament model needs --map sarcomere_length=component.variable (an output)");
      ca_input_ = mapped_["Ca_i"];
      if (m_.quantities[ca_input_].role == Role::state || m_.quantities[ca_input_].role == Role::time)
        throw ImportError(m_.source(ca_input_).path + ": " + m_.source(ca_input_).qualified() +
                          " is a state or time; the input Ca_i replaces a constant or an algebraic variable");
      if (!m_.source(ca_input_).unit.same_dims(molar_unit()))
        throw ImportError(m_.source(ca_input_).path + ": Ca_i is mapped to " + m_.source(ca_input_).qualified() +
                          ", which is not a concentration");
      notes_.push_back("input: Ca_i [mM] replaces " + m_.source(ca_input_).qualified() + " [" +
                       m_.source(ca_input_).units_name + "] and its equation");
      return;
    }
    find_voltage();
    find_stimulus();
    find_capacitance();
  }

  void find_voltage() {
    if (!o_.voltage.empty()) {
      v_ = quantity_named(o_.voltage, "--voltage");
      if (m_.quantities[v_].role != Role::state) throw ImportError("--voltage " + o_.voltage + ": not a state");
    } else {
      std::vector<int> candidates;
      for (int q : m_.states)
        if (m_.source(q).unit.same_dims(volt_unit())) candidates.push_back(q);
      if (candidates.size() > 1) {
        std::vector<int> named;
        for (int q : candidates)
          if (m_.source(q).name == "V" || m_.source(q).name == "Vm" || m_.source(q).name == "V_m" ||
              m_.source(q).name == "v")
            named.push_back(q);
        candidates = named;
      }
      if (candidates.size() != 1)
        throw ImportError(m_.doc.file + ": cannot tell which state is the membrane potential (" +
                          std::to_string(candidates.size()) + " candidates); name it with --voltage component.variable");
      v_ = candidates[0];
    }
    const auto& v = m_.source(v_);
    if (!v.unit.same_dims(volt_unit()))
      throw ImportError(v.path + ": the membrane potential " + v.qualified() + " is in '" + v.units_name + "', not a voltage");
    v_scale_ = v.unit.scale / 1e-3;  // V_mV = V_src * v_scale_
    if (v_scale_ != 1.0)
      notes_.push_back("V: the CellML's " + v.qualified() + " is in " + v.units_name + "; V_mV = V * " + lit(v_scale_));
  }

  bool current_like(int q) const {
    const Unit& u = m_.source(q).unit;
    Unit per_area = ampere_unit(), per_cap = ampere_unit();
    per_area.dims["metre"] = -2;
    for (const auto& [d, x] : farad_unit().dims) per_cap.dims[d] -= x;
    return u.same_dims(ampere_unit()) || u.same_dims(per_area) || u.same_dims(per_cap);
  }

  void find_stimulus() {
    const auto& rate_uses = dependencies(m_, m_.doc.equations[m_.quantities[v_].equation].rhs);
    if (!o_.stimulus.empty()) {
      stim_ = quantity_named(o_.stimulus, "--stimulus");
      if (m_.quantities[stim_].role != Role::algebraic && m_.quantities[stim_].role != Role::parameter)
        throw ImportError("--stimulus " + o_.stimulus + ": not a constant or an algebraic variable");
    } else {
      // The stimulus: a current the rate of V uses that changes with time by
      // itself (a pulse train), and not through another such current.
      std::vector<int> candidates;
      for (int q : m_.order) {
        if (!rate_uses[q] || !current_like(q)) continue;
        if (!dependencies(m_, m_.doc.equations[m_.quantities[q].equation].rhs)[m_.time]) continue;
        candidates.push_back(q);
      }
      std::vector<int> outermost;
      for (int q : candidates) {
        bool used_by_other = false;
        for (int other : candidates)
          if (other != q && dependencies(m_, m_.doc.equations[m_.quantities[other].equation].rhs)[q])
            used_by_other = true;
        if (!used_by_other) outermost.push_back(q);
      }
      if (outermost.size() > 1) {
        std::string names;
        for (int q : outermost) names += " " + m_.source(q).qualified();
        throw ImportError(m_.doc.file + ": several time-dependent currents could be the stimulus (" + names +
                          " ); name it with --stimulus component.variable");
      }
      if (outermost.empty()) {
        notes_.push_back("stimulus: none found in the CellML (no time-dependent current in dV/dt); i_ext is added "
                         "to dV/dt as i_ext / C_pF");
        return;
      }
      stim_ = outermost[0];
    }
    if (!rate_uses[stim_])
      throw ImportError("the stimulus " + m_.source(stim_).qualified() + " is not used by dV/dt");
    // dV/dt must be linear in it: its effect is then replaced exactly by i_ext / C.
    Evaluator e(m_);
    e.pinned.assign(m_.quantities.size(), 0);
    e.pinned[stim_] = 1;
    auto rate_at = [&](double s) {
      e.values[stim_] = s;
      e.update();
      return e.rate(v_);
    };
    const double r0 = rate_at(0.0), r1 = rate_at(1.0), r2 = rate_at(2.0);
    gain_ = r1 - r0;  // d(dV/dt)/d(stim) in source units
    if (!(std::fabs(gain_) > 0) || std::fabs((r2 - r0) - 2 * gain_) > 1e-9 * std::fabs(gain_) + 1e-300)
      throw ImportError("the stimulus " + m_.source(stim_).qualified() + " does not enter dV/dt linearly");
  }

  void find_capacitance() {
    // Whole-cell pA in, mV/ms out: C_pF such that dV/dt gains i_ext / C_pF.
    const double per_si = stim_ >= 0 ? gain_ * v_scale_ * time_scale_ / m_.source(stim_).unit.scale : 0.0;
    std::string how;
    Unit per_area = ampere_unit();
    per_area.dims["metre"] = -2;
    if (stim_ >= 0 && m_.source(stim_).unit.same_dims(ampere_unit())) {
      capacitance_pF_ = snapped(1e12 / std::fabs(per_si));
      // The CellML's own capacitance, when it is a constant in pF, is the parameter.
      for (int q : m_.parameters) {
        const auto& s = m_.source(q);
        if (s.unit.same_dims(farad_unit()) && std::fabs(s.unit.scale - 1e-12) < 1e-24 &&
            std::fabs(m_.quantities[q].initial - capacitance_pF_) <= 1e-9 * capacitance_pF_)
          c_param_ = q;
      }
      how = c_param_ >= 0 ? "the CellML's " + m_.source(c_param_).qualified() + " [pF] is the capacitance parameter"
                          : "whole-cell currents: C_pF = " + lit(capacitance_pF_) +
                                " pF, from dV/dt's response to the stimulus";
    } else if (stim_ >= 0 && m_.source(stim_).unit.same_dims(per_area)) {
      const double cm_F_per_m2 = 1.0 / std::fabs(per_si);
      const double area_m2 = 1e-8;  // 1e-4 cm^2 (a 100 um x 100 um patch)
      capacitance_pF_ = snapped(cm_F_per_m2 * area_m2 * 1e12);
      area_note_ = "currents per membrane area: specific capacitance " + lit(cm_F_per_m2 * 100) +
                   " uF/cm^2 (from dV/dt's response to the stimulus); C_pF = Cm x membrane area, default area "
                   "1e-4 cm^2 (area_cm2 = 1e-6 C_pF / Cm_uF_per_cm2)";
      how = area_note_;
    } else {
      capacitance_pF_ = 100.0;
      how = stim_ >= 0 ? "currents per capacitance: C_pF (default 100 pF) scales i_ext into the model's A/F"
                       : "C_pF (default 100 pF) scales i_ext into dV/dt";
    }
    notes_.push_back("capacitance: " + how + "; i_ext [pA] enters dV/dt as i_ext / C_pF, and I_ion = i_ext - C_pF dV/dt");
    if (stim_ >= 0)
      notes_.push_back("stimulus removed: " + m_.source(stim_).qualified() + " [" + m_.source(stim_).units_name +
                       "] is 0 (fibrodem's i_ext and manifests pace the cell)");
  }

  // ---- roles in the generated code -----------------------------------------------

  void classify() {
    const int n = static_cast<int>(m_.quantities.size());
    lane_.assign(n, false);
    timed_.assign(n, false);
    for (int q : m_.states) lane_[q] = true;
    timed_[m_.time] = true;
    if (ca_input_ >= 0) lane_[ca_input_] = true;
    for (int q : m_.order) {
      if (q == stim_ || q == ca_input_) continue;
      for (int u : m_.quantities[q].uses) {
        if (u == stim_) continue;
        lane_[q] = lane_[q] || lane_[u];
        timed_[q] = timed_[q] || timed_[u];
      }
    }
    // What the rates and outputs need.
    needed_.assign(n, false);
    std::vector<int> stack(m_.states.begin(), m_.states.end());
    for (const auto& [signal, q] : mapped_) stack.push_back(q);
    if (c_param_ >= 0) stack.push_back(c_param_);
    while (!stack.empty()) {
      const int q = stack.back();
      stack.pop_back();
      if (needed_[q]) continue;
      needed_[q] = true;
      if (q == stim_ || q == ca_input_) continue;
      for (int u : m_.quantities[q].uses) stack.push_back(u);
    }
    std::string unused;
    for (int q : m_.parameters)
      if (!needed_[q]) unused += " " + m_.source(q).qualified();
    if (!unused.empty()) notes_.push_back("constants used only by what was removed, left out:" + unused);
    // Gates: alpha/beta or inf/tau forms of a dimensionless state in [0, 1].
    gates_.assign(n, Gate{});
    for (int q : m_.states)
      if (q != v_) gates_[q] = recognise_gate(q);
  }

  struct Gate {
    enum class Form { none, inf_tau, alpha_beta } form = Form::none;
    const Expr* first = nullptr;   // inf or alpha
    const Expr* second = nullptr;  // tau or beta
    bool gate = false;             // in [0, 1]: Rush-Larsen's gate
    bool voltage_only = false;
  };

  bool is_state_ref(const Expr& e, int q) const {
    return e.kind == Expr::Kind::variable && m_.quantity_of[e.var] == q && m_.factor_to(e.var) == 1.0;
  }
  static bool is_one(const Expr& e) { return e.kind == Expr::Kind::number && e.value == 1.0; }
  static bool is_op(const Expr& e, const char* op, std::size_t n) {
    return e.kind == Expr::Kind::apply && e.op == op && e.args.size() == n;
  }
  bool free_of(const Expr& e, int q) const { return !dependencies(m_, e)[q]; }

  Gate recognise_gate(int q) const {
    const Expr& rhs = m_.doc.equations[m_.quantities[q].equation].rhs;
    Gate g;
    // (inf - x) / tau
    if (is_op(rhs, "divide", 2) && is_op(rhs.args[0], "minus", 2) && is_state_ref(rhs.args[0].args[1], q) &&
        free_of(rhs.args[0].args[0], q) && free_of(rhs.args[1], q)) {
      g.form = Gate::Form::inf_tau;
      g.first = &rhs.args[0].args[0];
      g.second = &rhs.args[1];
    }
    // alpha (1 - x) - beta x, either order of the factors
    if (is_op(rhs, "minus", 2) && is_op(rhs.args[0], "times", 2) && is_op(rhs.args[1], "times", 2)) {
      const Expr* alpha = nullptr;
      const Expr* beta = nullptr;
      for (int i = 0; i < 2; ++i) {
        const Expr& f = rhs.args[0].args[i];
        if (is_op(f, "minus", 2) && is_one(f.args[0]) && is_state_ref(f.args[1], q)) alpha = &rhs.args[0].args[1 - i];
        if (is_state_ref(rhs.args[1].args[i], q)) beta = &rhs.args[1].args[1 - i];
      }
      if (alpha && beta && free_of(*alpha, q) && free_of(*beta, q)) {
        g.form = Gate::Form::alpha_beta;
        g.first = alpha;
        g.second = beta;
      }
    }
    if (g.form == Gate::Form::none) return g;
    const auto& s = m_.source(q);
    g.gate = s.unit.dims.empty() && s.unit.scale == 1.0 && m_.quantities[q].initial >= 0.0 &&
             m_.quantities[q].initial <= 1.0;
    std::vector<bool> deps = dependencies(m_, *g.first);
    const auto more = dependencies(m_, *g.second);
    for (std::size_t k = 0; k < deps.size(); ++k) deps[k] = deps[k] || more[k];
    // voltage_only: a, b depend on V and constants alone (through any algebraic chain).
    g.voltage_only = g.gate;
    for (std::size_t k = 0; k < deps.size(); ++k)
      if (deps[k] && (timed_[k] || static_cast<int>(k) == ca_input_ ||
                      (m_.quantities[k].role == Role::state && static_cast<int>(k) != v_)))
        g.voltage_only = false;
    return g;
  }

  void name_quantities() {
    const int n = static_cast<int>(m_.quantities.size());
    ident_.assign(n, "");
    std::map<std::string, int> count;
    for (int q = 0; q < n; ++q) ++count[sanitize(m_.source(q).name)];
    std::set<std::string> taken;
    for (int q = 0; q < n; ++q) {
      const auto& s = m_.source(q);
      std::string id = sanitize(s.name);
      if (count[id] > 1 || reserved().count(id)) id = sanitize(s.component + "_" + s.name);
      while (taken.count(id) || reserved().count(id)) id += "_";
      taken.insert(id);
      ident_[q] = id;
    }
    ident_[m_.time] = "time";
  }

  // ---- expressions ----------------------------------------------------------------

  static std::string as_lane(const Code& c) { return c.lane ? c.text : "R(" + c.text + ")"; }
  static std::string as_mask(const Code& c) {
    return c.lane ? c.text : "(R(" + c.text + " ? 1.0 : 0.0) != R(0.0))";
  }

  Code variable(int v) const {
    const int q = m_.quantity_of[v];
    if (q == stim_) return {"0.0", false, false};
    const double f = m_.factor_to(v);
    std::string text = ident_[q];
    if (f != 1.0) text = "(" + text + " * " + lit(f) + ")";
    return {text, lane_[q], false};
  }

  Code emit(const Expr& e) {
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
    if (e.op == "divide")
      if (auto rewritten = removable_singularity(e)) return *rewritten;
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
    return {"cm_" + op + "(" + a[0].text + ")", lane, false};  // trigonometric and hyperbolic (prelude)
  }

  Code piecewise(const Expr& e) {
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

  // ---- x / (exp(x) - 1) forms ---------------------------------------------------

  // d(e)/dV as code, for expressions affine in V (nullopt: not handled; "" : zero).
  std::optional<std::string> derivative(const Expr& e) {
    const bool depends = (e.kind == Expr::Kind::variable && m_.quantity_of[e.var] == v_) || dependencies(m_, e)[v_];
    if (!depends) return std::string();
    if (e.kind == Expr::Kind::variable) {
      const int q = m_.quantity_of[e.var];
      if (q == v_) return lit(m_.factor_to(e.var));
      if (m_.quantities[q].role != Role::algebraic || q == stim_) return std::nullopt;
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
        if (static_cast<int>(i) != which) s += " * " + emit(e.args[i]).text;
      return "(" + s + ")";
    }
    if (e.op == "divide") {
      auto dd = derivative(e.args[1]);
      if (!dd || !dd->empty()) return std::nullopt;
      auto dn = derivative(e.args[0]);
      if (!dn) return std::nullopt;
      return "(" + *dn + " / " + emit(e.args[1]).text + ")";
    }
    return std::nullopt;
  }

  // The values of an expression as V sweeps the physiological range (others at
  // their initial values).
  std::vector<double> sweep_V(const Expr& e) {
    std::vector<double> out;
    Evaluator ev(m_);
    for (double v_mV : {-95.0, -60.0, -31.0, -7.0, 18.0, 47.0}) {
      ev.values[v_] = v_mV / v_scale_;
      ev.update();
      out.push_back(ev.eval(e));
    }
    return out;
  }

  // N / (exp(E) - 1) or N / (1 - exp(E)) with N (or a factor of it) a multiple
  // of E: 0/0 where E = 0. Rewritten as (N/E) * E/(exp(E) - 1) with N/E as the
  // ratio of their slopes in V and E/(exp(E) - 1) = exprel(-E) (simd.hpp), exact
  // at and around E = 0.
  std::optional<Code> removable_singularity(const Expr& e) {
    if (v_ < 0) return std::nullopt;
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
          if (&g != f) rest += emit(g).text + " * ";
      const Code x = emit(*exponent);
      std::string text = "(" + rest + (one_minus ? "(-" : "(") + *dN + " / " + *dE + ") * exprel(" +
                         (x.lane ? "" : "double") + "(-" + x.text + ")))";
      ++singularities_;
      singularity_paths_.push_back(e.path);
      return Code{text, emit(n).lane || x.lane, false};
    }
    return std::nullopt;
  }

  // ---- the file ---------------------------------------------------------------------

  std::string unit_label(int q) const {
    if (q == v_) return "mV";
    if (q == ca_input_) return "mM";
    return m_.source(q).units_name;
  }

  std::string source() {
    std::ostringstream body;
    // Parameters and per-block (double) quantities.
    std::vector<int> params;
    for (int q : m_.parameters)
      if (needed_[q] && q != stim_ && q != ca_input_) params.push_back(q);
    for (int q : params) body << "    [[maybe_unused]] const double " << ident_[q] << " = p[kP_" << ident_[q] << "];\n";
    const bool has_c = !o_.myofilament;
    if (has_c && c_param_ < 0) body << "    const double C_pF = p[kP_C_pF];\n";
    if (has_c && c_param_ >= 0) body << "    const double C_pF = " << ident_[c_param_] << ";\n";
    body << "    [[maybe_unused]] const double time = t_ms * " << lit(time_scale_) << ";  // in "
         << m_.source(m_.time).units_name << "\n";
    for (int q : m_.order)
      if (needed_[q] && !lane_[q] && q != stim_ && q != ca_input_) body << "    " << assignment(q, "const double");
    body << "    fibrodem::for_each_lane_group(block, [&](const auto& cell) {\n"
         << "      using R = typename std::decay_t<decltype(cell)>::Real;\n";
    for (std::size_t k = 0; k < state_list().size(); ++k) {
      const int q = state_list()[k];
      body << "      [[maybe_unused]] const R " << ident_[q] << " = cell.state(kS_" << ident_[q] << ")";
      if (q == v_ && v_scale_ != 1.0) body << " * " << lit(1.0 / v_scale_);
      body << ";\n";
    }
    if (ca_input_ >= 0)
      body << "      const R " << ident_[ca_input_] << " = cell.input(kIn_Ca_i) * "
           << lit(1.0 / m_.source(ca_input_).unit.scale) << ";  // mM -> " << m_.source(ca_input_).units_name << "\n";
    for (int q : m_.order)
      if (needed_[q] && lane_[q] && q != stim_ && q != ca_input_) body << "      " << assignment(q, "const R");
    // Rates, in fibrodem's units per ms.
    for (int q : state_list()) {
      const double m = m_.rate_factor(q) * time_scale_ * (q == v_ ? v_scale_ : 1.0);
      const std::string k = "kS_" + ident_[q];
      const Gate& g = gates_[q];
      if (g.form == Gate::Form::none || q == v_) {
        const Code rhs = emit(m_.doc.equations[m_.quantities[q].equation].rhs);
        std::string rate = as_lane(rhs) + (m == 1.0 ? "" : " * " + lit(m));
        if (q == v_) {
          body << "      const R dV_dt = " << rate << " + cell.input(kIn_i_ext) / C_pF;  // mV/ms\n"
               << "      cell.rate(" << k << ", dV_dt);\n";
        } else {
          body << "      cell.rate(" << k << ", " << rate << ");\n";
        }
        continue;
      }
      const Code a = emit(*g.first), b = emit(*g.second);
      const std::string ms = m == 1.0 ? "" : " * " + lit(m);
      if (g.gate && g.form == Gate::Form::alpha_beta)
        body << "      cell.gate_alpha_beta(" << k << ", " << as_lane(a) << ms << ", " << as_lane(b) << ms << ");\n";
      else if (g.gate)
        body << "      cell.gate_inf_tau(" << k << ", " << as_lane(a) << ", " << as_lane(b)
             << (m == 1.0 ? "" : " / " + lit(m)) << ");\n";
      else if (g.form == Gate::Form::alpha_beta)
        body << "      cell.linear(" << k << ", " << as_lane(a) << ms << ", -(" << as_lane(a) << " + " << as_lane(b)
             << ")" << ms << ");\n";
      else
        body << "      cell.linear(" << k << ", " << as_lane(a) << " / " << as_lane(b) << ms << ", R(-1.0) / "
             << as_lane(b) << ms << ");\n";
    }
    // Outputs.
    if (!o_.myofilament) body << "      cell.output(kOut_I_ion, cell.input(kIn_i_ext) - C_pF * dV_dt);\n";
    for (const auto& [signal, q] : mapped_) {
      if (signal == "Ca_i" && o_.myofilament) continue;
      const Code c{ident_[q], lane_[q], false};
      body << "      cell.output(kOut_" << sanitize(signal) << ", " << as_lane(c);
      if (const double f = output_factor(signal, q); f != 1.0) body << " * " << lit(f);
      body << ");\n";
    }
    body << "    });\n";
    const std::string head = header();
    const std::string decl = declarations(params);
    return head + decl + "  void evaluate(const fibrodem::BlockView& block, double t_ms) const override {\n"
           "    const double* p = block.params;\n" + body.str() + "  }\n\n private:\n  fibrodem::ModelInfo info_;\n};\n\n"
           "}  // namespace\n\nFIBRODEM_CELL_MODEL_PLUGIN(" + class_name() + ")\n";
  }

  double output_factor(const std::string& signal, int q) const {
    const auto& s = m_.source(q);
    if (signal == "Ca_i") {
      if (!s.unit.same_dims(molar_unit()))
        throw ImportError(s.path + ": Ca_i is mapped to " + s.qualified() + " [" + s.units_name + "], not a concentration");
      return s.unit.scale;  // mol/m^3 = mM
    }
    if (signal == "sarcomere_length") {
      Unit metre;
      metre.dims["metre"] = 1;
      if (!s.unit.same_dims(metre))
        throw ImportError(s.path + ": sarcomere_length is mapped to " + s.qualified() + ", not a length");
      return s.unit.scale / 1e-6;  // um
    }
    return 1.0;
  }

  std::string output_unit(const std::string& signal, int q) const {
    if (signal == "Ca_i") return "mM";
    if (signal == "sarcomere_length") return "um";
    return m_.source(q).units_name;
  }

  const std::vector<int>& state_list() const { return m_.states; }

  std::string assignment(int q, const char* type) {
    const auto& eq = m_.doc.equations[m_.quantities[q].equation];
    Code c = emit(eq.rhs);
    const double f = 1.0 / m_.factor_to(eq.lhs);
    std::string text = std::string(type) == "const R" ? as_lane(c) : c.text;
    if (c.boolean) text = "(" + text + " ? 1.0 : 0.0)";
    if (f != 1.0) text += " * " + lit(f);
    return "[[maybe_unused]] " + std::string(type) + " " + ident_[q] + " = " + text + ";  // " +
           m_.source(q).qualified() + " [" + m_.source(q).units_name + "]\n";
  }

  std::string class_name() const { return "Imported"; }

  std::string header() {
    std::ostringstream h;
    h << "// " << o_.name << ": a fibrodem cell-model plugin generated by `fibrodem import-cellml` from\n"
      << "// " << o_.source_name << " (CellML " << m_.doc.version << ", model '" << m_.doc.model_name << "').\n"
      << "// Import again rather than edit: every number below is the CellML's.\n//\n"
      << "// At fibrodem's boundary (time in ms, V in mV, i_ext and I_ion in whole-cell pA, C in pF):\n";
    std::vector<std::string> all = notes_;
    if (connections_converted() > 0)
      all.push_back("units: " + std::to_string(connections_converted()) +
                    " connected variables differ in units from their source and are converted where used");
    std::string gate_list, vo_list, linear_list;
    for (int q : m_.states) {
      const Gate& g = gates_[q];
      if (g.form == Gate::Form::none || q == v_) continue;
      const std::string form = g.form == Gate::Form::alpha_beta ? "alpha/beta" : "inf/tau";
      (g.gate ? gate_list : linear_list) += " " + ident_[q] + " (" + form + ")";
      if (g.voltage_only) vo_list += " " + ident_[q];
    }
    if (!gate_list.empty()) all.push_back("gates (Rush-Larsen, in [0, 1]):" + gate_list);
    if (!vo_list.empty()) all.push_back("voltage_only gates (lookup tables):" + vo_list);
    if (!linear_list.empty()) all.push_back("linear forms, not gates:" + linear_list);
    notes_ = all;
    for (const auto& n : all) h << "//   - " << wrap(n) << "\n";
    return h.str();
  }

  std::string wrap(const std::string& s) const {
    std::string out;
    std::size_t col = 7;
    std::istringstream words(s);
    std::string w;
    bool first = true;
    while (words >> w) {
      if (!first && col + w.size() + 1 > 100) {
        out += "\n//     ";
        col = 7;
      } else if (!first) {
        out += " ";
        ++col;
      }
      out += w;
      col += w.size();
      first = false;
    }
    return out;
  }

  int connections_converted() const {
    int n = 0;
    for (std::size_t v = 0; v < m_.doc.variables.size(); ++v)
      if (m_.factor_to(static_cast<int>(v)) != 1.0) ++n;
    return n;
  }

  std::string declarations(const std::vector<int>& params) {
    std::ostringstream d;
    if (singularities_ > 0) {
      std::string where;
      for (const auto& p : singularity_paths_) where += "\n//       " + p;
      d << "//   - removable singularities (x/(exp(x)-1) forms, 0/0 where x = 0) rewritten with exprel(): "
        << singularities_ << ", at" << where << "\n";
      notes_.push_back("removable singularities rewritten with exprel(): " + std::to_string(singularities_));
    }
    d << "#include <cmath>\n#include <limits>\n#include <type_traits>\n\n"
      << "#include \"model/block_access.hpp\"\n#include \"model/cell_model.hpp\"\n\nnamespace {\n\n"
      << "FIBRODEM_USE_LANE_MATH;\n\n" << prelude() << "\n";
    d << "enum State {";
    for (int q : m_.states) d << " kS_" << ident_[q] << ",";
    d << " kNumStates };\nenum Param {";
    for (int q : params) d << " kP_" << ident_[q] << ",";
    if (!o_.myofilament && c_param_ < 0) d << " kP_C_pF,";
    d << " kNumParams };\n";
    d << (o_.myofilament ? "enum Input { kIn_Ca_i };\n" : "enum Input { kIn_i_ext };\n");
    d << "enum Output {" << (o_.myofilament ? "" : " kOut_I_ion,");
    for (const auto& [signal, q] : mapped_)
      if (!(signal == "Ca_i" && o_.myofilament)) d << " kOut_" << sanitize(signal) << ",";
    d << " kNumOutputs };\n\n";
    d << "class " << class_name() << " final : public fibrodem::CellModel {\n public:\n  " << class_name() << "() {\n"
      << "    info_.name = \"" << o_.name << "\";\n    info_.version = \"1.0.0\";\n"
      << "    info_.description = \"Imported from CellML " << m_.doc.version << " model '" << m_.doc.model_name << "'.\";\n"
      << "    info_.reference = \"" << o_.source_name << "\";\n"
      << "    info_.kind = fibrodem::ModelKind::" << (o_.myofilament ? "myofilament" : "ionic") << ";\n"
      << "    info_.states = {\n";
    for (int q : m_.states) {
      const Gate& g = gates_[q];
      double lower = -1e300, upper = 1e300, initial = m_.quantities[q].initial;
      if (q == v_) {
        lower = -500.0;
        upper = 500.0;
        initial *= v_scale_;
      } else if (g.gate) {
        lower = 0.0;
        upper = 1.0;
      } else if (m_.source(q).unit.same_dims(molar_unit()) && initial >= 0.0) {
        lower = 0.0;
      }
      d << "        {\"" << ident_[q] << "\", \"" << unit_label(q) << "\", " << lit(initial) << ", " << lit(lower)
        << ", " << lit(upper) << ", " << (g.gate ? "true" : "false") << ", " << (g.voltage_only ? "true" : "false")
        << "},  // " << m_.source(q).qualified() << "\n";
    }
    d << "    };\n    info_.parameters = {\n";
    for (int q : params)
      d << "        {\"" << ident_[q] << "\", \"" << m_.source(q).units_name << "\", " << lit(m_.quantities[q].initial)
        << ", \"CellML " << m_.source(q).qualified() << "\"},\n";
    if (!o_.myofilament && c_param_ < 0)
      d << "        {\"C_pF\", \"pF\", " << lit(capacitance_pF_) << ", \"membrane capacitance: i_ext / C_pF enters dV/dt"
        << (area_note_.empty() ? "" : " (C_pF = specific capacitance x membrane area)") << "\"},\n";
    d << "    };\n";
    if (o_.myofilament)
      d << "    info_.inputs = {{\"Ca_i\", \"mM\", \"cytosolic Ca2+ of the host myocyte\"}};\n";
    else
      d << "    info_.inputs = {{\"i_ext\", \"pA\", \"stimulus and gap-junction current, + depolarising\"}};\n";
    d << "    info_.outputs = {\n";
    if (!o_.myofilament) d << "        {\"I_ion\", \"pA\", \"total ionic current, + outward (i_ext - C dV/dt)\"},\n";
    for (const auto& [signal, q] : mapped_)
      if (!(signal == "Ca_i" && o_.myofilament))
        d << "        {\"" << signal << "\", \"" << output_unit(signal, q) << "\", \"CellML " << m_.source(q).qualified()
          << "\"},\n";
    d << "    };\n";
    if (!o_.myofilament) {
      int vk = 0;
      for (std::size_t k = 0; k < m_.states.size(); ++k)
        if (m_.states[k] == v_) vk = static_cast<int>(k);
      d << "    info_.voltage_state = " << vk << ";\n    info_.capacitance_parameter = kP_"
        << (c_param_ >= 0 ? ident_[c_param_] : std::string("C_pF")) << ";\n";
    }
    d << "  }\n\n  const fibrodem::ModelInfo& info() const override { return info_; }\n\n";
    return d.str();
  }

  static std::string prelude() {
    return R"(// Functions the lane math does not carry, for double and for lanes.
template <class T>
[[maybe_unused]] FIBRODEM_LANE_INLINE T square(const T& x) { return x * x; }
[[maybe_unused]] FIBRODEM_LANE_INLINE double cm_rem(double a, double b) { return std::fmod(a, b); }
[[maybe_unused]] FIBRODEM_LANE_INLINE fibrodem::simd::Real cm_rem(const fibrodem::simd::Real& a,
                                                                  const fibrodem::simd::Real& b) {
  return xsimd::fmod(a, b);
}
#define FIBRODEM_CELLML_UNARY(name, for_double, for_lanes)                                        \
  [[maybe_unused]] FIBRODEM_LANE_INLINE double name(double x) { return for_double; }              \
  [[maybe_unused]] FIBRODEM_LANE_INLINE fibrodem::simd::Real name(const fibrodem::simd::Real& x) { \
    return for_lanes;                                                                               \
  }
FIBRODEM_CELLML_UNARY(cm_sin, std::sin(x), xsimd::sin(x))
FIBRODEM_CELLML_UNARY(cm_cos, std::cos(x), xsimd::cos(x))
FIBRODEM_CELLML_UNARY(cm_tan, std::tan(x), xsimd::tan(x))
FIBRODEM_CELLML_UNARY(cm_sec, 1.0 / std::cos(x), 1.0 / xsimd::cos(x))
FIBRODEM_CELLML_UNARY(cm_csc, 1.0 / std::sin(x), 1.0 / xsimd::sin(x))
FIBRODEM_CELLML_UNARY(cm_cot, 1.0 / std::tan(x), 1.0 / xsimd::tan(x))
FIBRODEM_CELLML_UNARY(cm_sinh, std::sinh(x), xsimd::sinh(x))
FIBRODEM_CELLML_UNARY(cm_cosh, std::cosh(x), xsimd::cosh(x))
FIBRODEM_CELLML_UNARY(cm_tanh, std::tanh(x), xsimd::tanh(x))
FIBRODEM_CELLML_UNARY(cm_sech, 1.0 / std::cosh(x), 1.0 / xsimd::cosh(x))
FIBRODEM_CELLML_UNARY(cm_csch, 1.0 / std::sinh(x), 1.0 / xsimd::sinh(x))
FIBRODEM_CELLML_UNARY(cm_coth, 1.0 / std::tanh(x), 1.0 / xsimd::tanh(x))
FIBRODEM_CELLML_UNARY(cm_arcsin, std::asin(x), xsimd::asin(x))
FIBRODEM_CELLML_UNARY(cm_arccos, std::acos(x), xsimd::acos(x))
FIBRODEM_CELLML_UNARY(cm_arctan, std::atan(x), xsimd::atan(x))
FIBRODEM_CELLML_UNARY(cm_arcsec, std::acos(1.0 / x), xsimd::acos(1.0 / x))
FIBRODEM_CELLML_UNARY(cm_arccsc, std::asin(1.0 / x), xsimd::asin(1.0 / x))
FIBRODEM_CELLML_UNARY(cm_arccot, std::atan(1.0 / x), xsimd::atan(1.0 / x))
FIBRODEM_CELLML_UNARY(cm_arcsinh, std::asinh(x), xsimd::asinh(x))
FIBRODEM_CELLML_UNARY(cm_arccosh, std::acosh(x), xsimd::acosh(x))
FIBRODEM_CELLML_UNARY(cm_arctanh, std::atanh(x), xsimd::atanh(x))
FIBRODEM_CELLML_UNARY(cm_arcsech, std::acosh(1.0 / x), xsimd::acosh(1.0 / x))
FIBRODEM_CELLML_UNARY(cm_arccsch, std::asinh(1.0 / x), xsimd::asinh(1.0 / x))
FIBRODEM_CELLML_UNARY(cm_arccoth, std::atanh(1.0 / x), xsimd::atanh(1.0 / x))
#undef FIBRODEM_CELLML_UNARY
)";
  }

  std::string cmake() const {
    return "# The plugin " + o_.name + ", generated by `fibrodem import-cellml` from " + o_.source_name + ".\n"
           "# Build it with an installed fibrodem (its SDK):\n"
           "#   cmake -S . -B build -DCMAKE_PREFIX_PATH=/where/fibrodem/is/installed && cmake --build build\n"
           "cmake_minimum_required(VERSION 3.20)\n"
           "project(fibrodem_plugin_" + o_.name + " LANGUAGES CXX)\n"
           "find_package(fibrodem REQUIRED)\n"
           "fibrodem_add_cell_model(" + o_.name + " " + o_.name + ".cpp)\n";
  }

  const Model& m_;
  const WriterOptions& o_;
  std::vector<std::string> notes_;
  std::map<std::string, int> mapped_;
  double time_scale_ = 1.0, v_scale_ = 1.0, gain_ = 0.0, capacitance_pF_ = 100.0;
  std::string area_note_;
  int v_ = -1, stim_ = -1, c_param_ = -1, ca_input_ = -1;
  std::vector<bool> lane_, timed_, needed_;
  std::vector<Gate> gates_;
  std::vector<std::string> ident_;
  int singularities_ = 0;
  std::vector<std::string> singularity_paths_;
};

}  // namespace

GeneratedPlugin write_plugin(const Model& model, const WriterOptions& options) {
  return Writer(model, options).run();
}

}  // namespace fibrodem::cellml
