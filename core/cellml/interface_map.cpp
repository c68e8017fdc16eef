#include "cellml/interface_map.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

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

  void find_voltage() {
    if (!o_.voltage.empty()) {
      b_.v = quantity_named(o_.voltage, "--voltage");
      if (m_.quantities[b_.v].role != Role::state) throw ImportError("--voltage " + o_.voltage + ": not a state");
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
      b_.v = candidates[0];
    }
    const auto& v = m_.source(b_.v);
    if (!v.unit.same_dims(volt_unit()))
      throw ImportError(v.path + ": the membrane potential " + v.qualified() + " is in '" + v.units_name + "', not a voltage");
    b_.v_scale = v.unit.scale / 1e-3;  // V_mV = V_src * v_scale
    if (b_.v_scale != 1.0)
      b_.notes.push_back("V: the CellML's " + v.qualified() + " is in " + v.units_name + "; V_mV = V * " + lit(b_.v_scale));
  }

  bool current_like(int q) const {
    const Unit& u = m_.source(q).unit;
    Unit per_area = ampere_unit(), per_cap = ampere_unit();
    per_area.dims["metre"] = -2;
    for (const auto& [d, x] : farad_unit().dims) per_cap.dims[d] -= x;
    return u.same_dims(ampere_unit()) || u.same_dims(per_area) || u.same_dims(per_cap);
  }

  void find_stimulus() {
    const auto& rate_uses = dependencies(m_, m_.doc.equations[m_.quantities[b_.v].equation].rhs);
    if (!o_.stimulus.empty()) {
      b_.stim = quantity_named(o_.stimulus, "--stimulus");
      if (m_.quantities[b_.stim].role != Role::algebraic && m_.quantities[b_.stim].role != Role::parameter)
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
        b_.notes.push_back("stimulus: none found in the CellML (no time-dependent current in dV/dt); i_ext is added "
                           "to dV/dt as i_ext / C_pF");
        return;
      }
      b_.stim = outermost[0];
    }
    const int stim = b_.stim;
    if (!rate_uses[stim])
      throw ImportError("the stimulus " + m_.source(stim).qualified() + " is not used by dV/dt");
    // dV/dt must be linear in it: its effect is then replaced exactly by i_ext / C.
    Evaluator e(m_);
    e.pinned.assign(m_.quantities.size(), 0);
    e.pinned[stim] = 1;
    auto rate_at = [&](double s) {
      e.values[stim] = s;
      e.update();
      return e.rate(b_.v);
    };
    const double r0 = rate_at(0.0), r1 = rate_at(1.0), r2 = rate_at(2.0);
    b_.gain = r1 - r0;  // d(dV/dt)/d(stim) in source units
    if (!(std::fabs(b_.gain) > 0) || std::fabs((r2 - r0) - 2 * b_.gain) > 1e-9 * std::fabs(b_.gain) + 1e-300)
      throw ImportError("the stimulus " + m_.source(stim).qualified() + " does not enter dV/dt linearly");
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
    b_.notes.push_back("capacitance: " + how + "; i_ext [pA] enters dV/dt as i_ext / C_pF, and I_ion = i_ext - C_pF dV/dt");
    if (stim >= 0)
      b_.notes.push_back("stimulus removed: " + m_.source(stim).qualified() + " [" + m_.source(stim).units_name +
                         "] is 0 (fibrodem's i_ext and manifests pace the cell)");
  }

  const Model& m_;
  const WriterOptions& o_;
  InterfaceMap b_;
};

}  // namespace

InterfaceMap map_interface(const Model& model, const WriterOptions& options) { return Mapper(model, options).run(); }

}  // namespace fibrodem::cellml
