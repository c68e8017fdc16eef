#include "cellml/interface_map.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>

#include "cellml/import_error.hpp"

namespace fibrodem::cellml {

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

namespace {

class Mapper {
 public:
  Mapper(const Model& m, const WriterOptions& o) : m_(m), o_(o) {}

  InterfaceMap run() {
    find_boundary();
    return b_;
  }

 private:
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
    // t_src = t_ms * time_scale
    b_.time_scale = 1e-3 / time_unit.unit.scale;
    if (b_.time_scale != 1.0)
      b_.notes.push_back("time: the CellML's " + time_unit.qualified() + " is in " + time_unit.units_name +
                         "; time = t_ms * " + lit(b_.time_scale) + ", rates * " + lit(b_.time_scale) + " per ms");
    for (const auto& [signal, target] : o_.map) b_.mapped[signal] = quantity_named(target, "--map " + signal);
    if (o_.myofilament) {
      if (!b_.mapped.count("Ca_i")) throw ImportError("a myofilament model needs --map Ca_i=component.variable (its input)");
      if (!b_.mapped.count("sarcomere_length"))
        throw ImportError("a myofilament model needs --map sarcomere_length=component.variable (an output)");
      b_.ca_input = b_.mapped["Ca_i"];
      const int ca = b_.ca_input;
      if (m_.quantities[ca].role == Role::state || m_.quantities[ca].role == Role::time)
        throw ImportError(m_.source(ca).path + ": " + m_.source(ca).qualified() +
                          " is a state or time; the input Ca_i replaces a constant or an algebraic variable");
      if (!m_.source(ca).unit.same_dims(molar_unit()))
        throw ImportError(m_.source(ca).path + ": Ca_i is mapped to " + m_.source(ca).qualified() +
                          ", which is not a concentration");
      b_.notes.push_back("input: Ca_i [mM] replaces " + m_.source(ca).qualified() + " [" + m_.source(ca).units_name +
                         "] and its equation");
      return;
    }
    find_voltage();
    find_stimulus();
    find_capacitance();
  }

  // Quantities a variable of which carries the oxmeta term, in RDF or as its id.
  std::vector<int> annotated(const std::string& term) const {
    std::vector<int> out;
    for (int q = 0; q < static_cast<int>(m_.quantities.size()); ++q)
      for (int v : m_.quantities[q].members) {
        const auto& var = m_.doc.variables[v];
        if (var.id == term || std::find(var.oxmeta.begin(), var.oxmeta.end(), term) != var.oxmeta.end()) {
          out.push_back(q);
          break;
        }
      }
    return out;
  }

  // The name (of any of its connected variables) among `names`, case aside; "" if none.
  std::string name_among(int q, const std::set<std::string>& names) const {
    for (int v : m_.quantities[q].members) {
      std::string lower = m_.doc.variables[v].name;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (names.count(lower)) return m_.doc.variables[v].name;
    }
    return "";
  }

  std::string list(const std::vector<int>& qs) const {
    std::string names;
    for (int q : qs) names += (names.empty() ? "" : ", ") + m_.source(q).qualified();
    return names;
  }

  void find_voltage() {
    const std::string oxmeta = "membrane_voltage";
    if (!o_.voltage.empty()) {
      b_.v = quantity_named(o_.voltage, "--voltage");
      if (m_.quantities[b_.v].role != Role::state) throw ImportError("--voltage " + o_.voltage + ": not a state");
      b_.v_rule = "--voltage";
    } else if (const auto marked = annotated(oxmeta); !marked.empty()) {
      if (marked.size() > 1)
        throw ImportError(m_.doc.file + ": several variables are annotated " + oxmeta + " (" + list(marked) +
                          "); name the potential with --voltage component.variable");
      b_.v = marked[0];
      if (m_.quantities[b_.v].role != Role::state)
        throw ImportError(m_.source(b_.v).path + ": " + m_.source(b_.v).qualified() + " is annotated " + oxmeta +
                          " but is not a state; name the potential with --voltage component.variable");
      b_.v_rule = "annotation: oxmeta " + oxmeta;
    } else {
      static const std::set<std::string> names = {"v", "vm", "v_m", "membrane_voltage", "membrane_potential",
                                                  "v_membrane"};
      std::vector<int> in_volts, named;
      for (int q : m_.states)
        if (m_.source(q).unit.same_dims(volt_unit())) {
          in_volts.push_back(q);
          if (!name_among(q, names).empty()) named.push_back(q);
        }
      if (named.size() == 1) {
        b_.v = named[0];
        b_.v_rule = "name: " + name_among(b_.v, names);
      } else if (named.empty() && in_volts.size() == 1) {
        b_.v = in_volts[0];
        b_.v_rule = "units: the only state in volts";
      } else {
        const auto& shown = named.empty() ? in_volts : named;
        throw ImportError(m_.doc.file + ": cannot tell which state is the membrane potential (" +
                          std::to_string(shown.size()) + " candidates" + (shown.empty() ? "" : ": " + list(shown)) +
                          "); name it with --voltage component.variable");
      }
    }
    const auto& v = m_.source(b_.v);
    if (!v.unit.same_dims(volt_unit()))
      throw ImportError(v.path + ": the membrane potential " + v.qualified() + " is in '" + v.units_name + "', not a voltage");
    b_.v_scale = v.unit.scale / 1e-3;  // V_mV = V_src * v_scale
    b_.notes.push_back("V: " + v.qualified() + " [" + v.units_name + "] is the membrane potential (rule: " + b_.v_rule +
                       "), the plugin's state V" +
                       (b_.v_scale != 1.0 ? "; V_mV = " + v.name + " * " + lit(b_.v_scale) : std::string()));
  }

  bool current_like(int q) const {
    const Unit& u = m_.source(q).unit;
    Unit per_area = ampere_unit(), per_cap = ampere_unit();
    per_area.dims["metre"] = -2;
    for (const auto& [d, x] : farad_unit().dims) per_cap.dims[d] -= x;
    return u.same_dims(ampere_unit()) || u.same_dims(per_area) || u.same_dims(per_cap);
  }

  // What q depends on through its equation (nothing for a constant).
  std::vector<bool> inputs_of(int q) const {
    if (m_.quantities[q].equation < 0) return std::vector<bool>(m_.quantities.size(), false);
    return dependencies(m_, m_.doc.equations[m_.quantities[q].equation].rhs);
  }

  // A state q depends on, or -1: a current that depends on a state is a
  // membrane current, never the stimulus.
  int state_dependency(int q) const {
    const auto deps = inputs_of(q);
    for (int s : m_.states)
      if (deps[s]) return s;
    return -1;
  }

  void find_stimulus() {
    const std::string oxmeta = "membrane_stimulus_current";
    const auto rate_uses = dependencies(m_, m_.doc.equations[m_.quantities[b_.v].equation].rhs);
    auto pulse_like = [&](int q) {
      const Role r = m_.quantities[q].role;
      return (r == Role::algebraic || r == Role::parameter) && rate_uses[q] && current_like(q) &&
             state_dependency(q) < 0;
    };
    if (!o_.stimulus.empty()) {
      b_.stim = quantity_named(o_.stimulus, "--stimulus");
      if (m_.quantities[b_.stim].role != Role::algebraic && m_.quantities[b_.stim].role != Role::parameter)
        throw ImportError("--stimulus " + o_.stimulus + ": not a constant or an algebraic variable");
      b_.stim_rule = "--stimulus";
    } else if (const auto marked = annotated(oxmeta); !marked.empty()) {
      if (marked.size() > 1)
        throw ImportError(m_.doc.file + ": several variables are annotated " + oxmeta + " (" + list(marked) +
                          "); name the stimulus with --stimulus component.variable");
      b_.stim = marked[0];
      b_.stim_rule = "annotation: oxmeta " + oxmeta;
    } else {
      static const std::set<std::string> names = {"i_stim", "istim", "i_stimulus", "stim_current",
                                                  "stimulus_current", "i_st", "i_app", "iapp", "i_applied",
                                                  "membrane_stimulus_current"};
      std::vector<int> named, timed;
      for (int q = 0; q < static_cast<int>(m_.quantities.size()); ++q) {
        if (!pulse_like(q)) continue;
        if (!name_among(q, names).empty()) named.push_back(q);
        if (m_.quantities[q].role == Role::algebraic && inputs_of(q)[m_.time]) timed.push_back(q);
      }
      // A chain of named currents (membrane.i_Stim = stimulus_protocol.Istim, a copy, a unit
      // conversion, a sign) is one stimulus: the one nearest dV/dt, used by none of the others.
      if (named.size() > 1) {
        std::vector<int> outermost;
        for (int q : named) {
          bool used_by_other = false;
          for (int other : named)
            if (other != q && inputs_of(other)[q]) used_by_other = true;
          if (!used_by_other) outermost.push_back(q);
        }
        if (outermost.size() == 1) named = outermost;
      }
      if (named.size() > 1)
        throw ImportError(m_.doc.file + ": several currents are named as a stimulus (" + list(named) +
                          "); name it with --stimulus component.variable");
      if (named.size() == 1) {
        b_.stim = named[0];
        b_.stim_rule = "name: " + name_among(b_.stim, names);
      } else {
        // A pulse train: a current of time and constants alone that dV/dt
        // uses; of a chain of such currents (a unit conversion, a sign), the
        // one dV/dt uses, not what it is made of.
        std::vector<int> outermost;
        for (int q : timed) {
          bool used_by_other = false;
          for (int other : timed)
            if (other != q && inputs_of(other)[q]) used_by_other = true;
          if (!used_by_other) outermost.push_back(q);
        }
        if (outermost.size() > 1)
          throw ImportError(m_.doc.file + ": several currents of time alone could be the stimulus (" +
                            list(outermost) + "); name it with --stimulus component.variable");
        if (outermost.empty()) {
          b_.notes.push_back("stimulus: none found in the CellML (no annotation, no stimulus name, no current of time "
                             "alone in dV/dt); i_ext is added to dV/dt as i_ext / C_pF");
          b_.summary = "V: " + m_.source(b_.v).qualified() + " (" + b_.v_rule + "); no stimulus in the CellML";
          return;
        }
        b_.stim = outermost[0];
        b_.stim_rule = "structure: a current of time and constants alone in dV/dt";
      }
    }
    const int stim = b_.stim;
    const auto& s = m_.source(stim);
    if (!rate_uses[stim])
      throw ImportError(s.path + ": the stimulus " + s.qualified() + " (" + b_.stim_rule + ") is not used by dV/dt");
    if (const int state = state_dependency(stim); state >= 0)
      throw ImportError(s.path + ": the stimulus " + s.qualified() + " (" + b_.stim_rule + ") depends on the state " +
                        m_.source(state).qualified() + "; a stimulus is a current of time and constants alone " +
                        "(name it with --stimulus component.variable)");
    if (!current_like(stim) && o_.stimulus.empty())
      throw ImportError(s.path + ": the stimulus " + s.qualified() + " (" + b_.stim_rule + ") is in '" + s.units_name +
                        "', not a current (A, A/m^2 or A/F)");
    // dV/dt must be linear in it: i_ext then enters dV/dt as i_ext / C_pF
    // exactly, and C_pF follows from the gain.
    Evaluator e(m_);
    e.pinned.assign(m_.quantities.size(), 0);
    e.pinned[stim] = 1;
    auto rate_at = [&](double x) {
      e.values[stim] = x;
      e.update();
      return e.rate(b_.v);
    };
    const double r0 = rate_at(0.0), r1 = rate_at(1.0), r2 = rate_at(2.0);
    b_.gain = r1 - r0;  // d(dV/dt)/d(stim) in source units
    if (!(std::fabs(b_.gain) > 0) || std::fabs((r2 - r0) - 2 * b_.gain) > 1e-9 * std::fabs(b_.gain) + 1e-300)
      throw ImportError(s.path + ": the stimulus " + s.qualified() + " (" + b_.stim_rule +
                        ") does not enter dV/dt linearly");
  }

  void find_capacitance() {
    const int stim = b_.stim;
    // Whole-cell pA in, mV/ms out: C_pF such that dV/dt gains i_ext / C_pF.
    const double per_si = stim >= 0 ? b_.gain * b_.v_scale * b_.time_scale / m_.source(stim).unit.scale : 0.0;
    std::string how;
    Unit per_area = ampere_unit();
    per_area.dims["metre"] = -2;
    if (stim >= 0 && m_.source(stim).unit.same_dims(ampere_unit())) {
      b_.capacitance_pF = snapped(1e12 / std::fabs(per_si));
      // The CellML's own capacitance, when it is a constant in pF, is the parameter.
      for (int q : m_.parameters) {
        const auto& s = m_.source(q);
        if (s.unit.same_dims(farad_unit()) && std::fabs(s.unit.scale - 1e-12) < 1e-24 &&
            std::fabs(m_.quantities[q].initial - b_.capacitance_pF) <= 1e-9 * b_.capacitance_pF)
          b_.c_param = q;
      }
      how = b_.c_param >= 0 ? "the CellML's " + m_.source(b_.c_param).qualified() + " [pF] is the capacitance parameter"
                            : "whole-cell currents: C_pF = " + lit(b_.capacitance_pF) +
                                  " pF, from dV/dt's response to the stimulus";
    } else if (stim >= 0 && m_.source(stim).unit.same_dims(per_area)) {
      const double cm_F_per_m2 = 1.0 / std::fabs(per_si);
      const double area_m2 = 1e-8;  // 1e-4 cm^2 (a 100 um x 100 um patch)
      b_.capacitance_pF = snapped(cm_F_per_m2 * area_m2 * 1e12);
      b_.area_note = "currents per membrane area: specific capacitance " + lit(cm_F_per_m2 * 100) +
                     " uF/cm^2 (from dV/dt's response to the stimulus); C_pF = Cm x membrane area, default area "
                     "1e-4 cm^2 (area_cm2 = 1e-6 C_pF / Cm_uF_per_cm2)";
      how = b_.area_note;
    } else {
      b_.capacitance_pF = 100.0;
      how = stim >= 0 ? "currents per capacitance: C_pF (default 100 pF) scales i_ext into the model's A/F"
                      : "C_pF (default 100 pF) scales i_ext into dV/dt";
    }
    if (stim >= 0) replace_stimulus();
    b_.notes.push_back("capacitance: " + how + "; i_ext [pA] enters dV/dt as i_ext / C_pF, and I_ion = i_ext - C_pF dV/dt");
  }

  // stim = i_ext * k [its units per pA] makes dV/dt gain i_ext / C_pF. A
  // whole-cell current is i_ext itself, converted and signed; a current per
  // area or per capacitance is i_ext over the cell's size, C_pF at run time.
  void replace_stimulus() {
    const auto& s = m_.source(b_.stim);
    const double per_pA = 1.0 / (b_.gain * b_.v_scale * b_.time_scale);
    std::string formula;
    if (s.unit.same_dims(ampere_unit())) {
      b_.stim_per_pA = snapped((b_.gain > 0 ? 1e-12 : -1e-12) / s.unit.scale);
      formula = s.name + " = i_ext * " + lit(b_.stim_per_pA);
    } else {
      b_.stim_per_pA = snapped(per_pA);
      b_.stim_over_C = true;
      formula = s.name + " = i_ext / C_pF * " + lit(b_.stim_per_pA);
    }
    std::string users;
    for (int q = 0; q < static_cast<int>(m_.quantities.size()); ++q) {
      const auto& uses = m_.quantities[q].uses;
      if (q == b_.stim || std::find(uses.begin(), uses.end(), b_.stim) == uses.end()) continue;
      const std::string name = m_.quantities[q].role == Role::state ? "d(" + m_.source(q).qualified() + ")/dt"
                                                                     : m_.source(q).qualified();
      users += (users.empty() ? "" : ", ") + name;
    }
    b_.notes.push_back("stimulus: " + s.qualified() + " [" + s.units_name + "] (rule: " + b_.stim_rule +
                       ") is fibrodem's input i_ext [pA, + depolarising] wherever it is used (" + users + "): " +
                       formula + "; its own pulse protocol is left out (manifests pace the cell)");
    b_.summary = "V: " + m_.source(b_.v).qualified() + " (" + b_.v_rule + "); stimulus: " + s.qualified() + " (" +
                 b_.stim_rule + ") replaced by i_ext";
  }

  const Model& m_;
  const WriterOptions& o_;
  InterfaceMap b_;
};

}  // namespace

InterfaceMap map_interface(const Model& model, const WriterOptions& options) { return Mapper(model, options).run(); }

}  // namespace fibrodem::cellml
