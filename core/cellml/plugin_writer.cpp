#include "cellml/plugin_writer.hpp"

#include <sstream>

#include "cellml/expression_writer.hpp"
#include "cellml/gate_form.hpp"
#include "cellml/import_error.hpp"
#include "cellml/interface_map.hpp"
#include "cellml/singularities.hpp"

namespace fibrodem::cellml {

namespace {

// Assembles the plugin's source: the header of notes, the metadata
// (ModelInfo), and evaluate(): parameters and per-block quantities in double,
// then per lane group of cells the states, the algebraic quantities they
// need and the rates (gates in their linear form).
class Writer {
 public:
  Writer(const Model& m, const WriterOptions& o)
      : m_(m), o_(o), b_(map_interface(m, o)), ident_(identifiers(m, b_.v)), expr_(m, b_, lane_, ident_),
        singular_(m, b_, expr_) {
    expr_.rewrite_divide = [this](const Expr& e) { return singular_.rewrite(e); };
  }

  GeneratedPlugin run() {
    notes_ = b_.notes;
    classify();
    GeneratedPlugin out;
    out.cpp = source();
    out.cmake = cmake();
    out.notes = notes_;
    return out;
  }

 private:
  // ---- roles in the generated code -----------------------------------------------

  void classify() {
    const int n = static_cast<int>(m_.quantities.size());
    lane_.assign(n, false);
    timed_.assign(n, false);
    for (int q : m_.states) lane_[q] = true;
    timed_[m_.time] = true;
    // The inputs, i_ext as the stimulus and Ca_i, are per cell: lanes.
    if (b_.ca_input >= 0) lane_[b_.ca_input] = true;
    if (b_.stim >= 0) lane_[b_.stim] = true;
    for (int q : m_.order) {
      if (q == b_.stim || q == b_.ca_input) continue;
      for (int u : m_.quantities[q].uses) {
        lane_[q] = lane_[q] || lane_[u];
        timed_[q] = timed_[q] || timed_[u];
      }
    }
    // What the rates and outputs need.
    needed_.assign(n, false);
    std::vector<int> stack(m_.states.begin(), m_.states.end());
    for (const auto& [signal, q] : b_.mapped) stack.push_back(q);
    if (b_.c_param >= 0) stack.push_back(b_.c_param);
    while (!stack.empty()) {
      const int q = stack.back();
      stack.pop_back();
      if (needed_[q]) continue;
      needed_[q] = true;
      if (q == b_.stim || q == b_.ca_input) continue;
      for (int u : m_.quantities[q].uses) stack.push_back(u);
    }
    std::string unused;
    for (int q : m_.parameters)
      if (!needed_[q]) unused += " " + m_.source(q).qualified();
    if (!unused.empty()) notes_.push_back("constants used only by what fibrodem's inputs replace, left out:" + unused);
    // Gates: alpha/beta or inf/tau forms of a dimensionless state in [0, 1].
    gates_.assign(n, GateForm{});
    for (int q : m_.states)
      if (q != b_.v) gates_[q] = recognise_gate(m_, b_, timed_, q);
  }

  // ---- the file ---------------------------------------------------------------------

  std::string unit_label(int q) const {
    if (q == b_.v) return "mV";
    if (q == b_.ca_input) return "mM";
    return m_.source(q).units_name;
  }

  std::string source() {
    std::ostringstream body;
    // Parameters and per-block (double) quantities.
    std::vector<int> params;
    for (int q : m_.parameters)
      if (needed_[q] && q != b_.stim && q != b_.ca_input) params.push_back(q);
    for (int q : params) body << "    [[maybe_unused]] const double " << ident_[q] << " = p[kP_" << ident_[q] << "];\n";
    const bool has_c = !o_.myofilament;
    if (has_c && b_.c_param < 0) body << "    const double C_pF = p[kP_C_pF];\n";
    if (has_c && b_.c_param >= 0) body << "    const double C_pF = " << ident_[b_.c_param] << ";\n";
    body << "    [[maybe_unused]] const double time = t_ms * " << lit(b_.time_scale) << ";  // in "
         << m_.source(m_.time).units_name << "\n";
    for (int q : m_.order)
      if (needed_[q] && !lane_[q] && q != b_.stim && q != b_.ca_input) body << "    " << assignment(q, "const double");
    body << "    fibrodem::for_each_lane_group(block, [&](const auto& cell) {\n"
         << "      using R = typename std::decay_t<decltype(cell)>::Real;\n";
    for (std::size_t k = 0; k < state_list().size(); ++k) {
      const int q = state_list()[k];
      body << "      [[maybe_unused]] const R " << ident_[q] << " = cell.state(kS_" << ident_[q] << ")";
      if (q == b_.v && b_.v_scale != 1.0) body << " * " << lit(1.0 / b_.v_scale);
      body << ";\n";
    }
    if (b_.ca_input >= 0)
      body << "      const R " << ident_[b_.ca_input] << " = cell.input(kIn_Ca_i) * "
           << lit(1.0 / m_.source(b_.ca_input).unit.scale) << ";  // mM -> " << m_.source(b_.ca_input).units_name << "\n";
    if (b_.stim >= 0)
      body << "      const R " << ident_[b_.stim] << " = cell.input(kIn_i_ext)" << (b_.stim_over_C ? " / C_pF" : "")
           << " * " << lit(b_.stim_per_pA) << ";  // " << m_.source(b_.stim).qualified() << " ["
           << m_.source(b_.stim).units_name << "]: the stimulus is i_ext [pA]\n";
    for (int q : m_.order)
      if (needed_[q] && lane_[q] && q != b_.stim && q != b_.ca_input) body << "      " << assignment(q, "const R");
    // Rates, in fibrodem's units per ms.
    for (int q : state_list()) {
      const double m = m_.rate_factor(q) * b_.time_scale * (q == b_.v ? b_.v_scale : 1.0);
      const std::string k = "kS_" + ident_[q];
      const GateForm& g = gates_[q];
      if (g.form == GateForm::Form::none || q == b_.v) {
        const Code rhs = expr_.emit(m_.doc.equations[m_.quantities[q].equation].rhs);
        std::string rate = ExpressionWriter::as_lane(rhs) + (m == 1.0 ? "" : " * " + lit(m));
        if (q == b_.v) {
          body << "      const R dV_dt = " << rate << (b_.stim >= 0 ? "" : " + cell.input(kIn_i_ext) / C_pF")
               << ";  // mV/ms\n"
               << "      cell.rate(" << k << ", dV_dt);\n";
        } else {
          body << "      cell.rate(" << k << ", " << rate << ");\n";
        }
        continue;
      }
      const Code a = expr_.emit(*g.first), b = expr_.emit(*g.second);
      const std::string ms = m == 1.0 ? "" : " * " + lit(m);
      if (g.gate && g.form == GateForm::Form::alpha_beta)
        body << "      cell.gate_alpha_beta(" << k << ", " << ExpressionWriter::as_lane(a) << ms << ", " << ExpressionWriter::as_lane(b) << ms << ");\n";
      else if (g.gate)
        body << "      cell.gate_inf_tau(" << k << ", " << ExpressionWriter::as_lane(a) << ", " << ExpressionWriter::as_lane(b)
             << (m == 1.0 ? "" : " / " + lit(m)) << ");\n";
      else if (g.form == GateForm::Form::alpha_beta)
        body << "      cell.linear(" << k << ", " << ExpressionWriter::as_lane(a) << ms << ", -(" << ExpressionWriter::as_lane(a) << " + " << ExpressionWriter::as_lane(b)
             << ")" << ms << ");\n";
      else
        body << "      cell.linear(" << k << ", " << ExpressionWriter::as_lane(a) << " / " << ExpressionWriter::as_lane(b) << ms << ", R(-1.0) / "
             << ExpressionWriter::as_lane(b) << ms << ");\n";
    }
    // Outputs.
    if (!o_.myofilament) body << "      cell.output(kOut_I_ion, cell.input(kIn_i_ext) - C_pF * dV_dt);\n";
    for (const auto& [signal, q] : b_.mapped) {
      if (signal == "Ca_i" && o_.myofilament) continue;
      const Code c{ident_[q], lane_[q], false};
      body << "      cell.output(kOut_" << sanitize(signal) << ", " << ExpressionWriter::as_lane(c);
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
    Code c = expr_.emit(eq.rhs);
    const double f = 1.0 / m_.factor_to(eq.lhs);
    std::string text = std::string(type) == "const R" ? ExpressionWriter::as_lane(c) : c.text;
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
      const GateForm& g = gates_[q];
      if (g.form == GateForm::Form::none || q == b_.v) continue;
      const std::string form = g.form == GateForm::Form::alpha_beta ? "alpha/beta" : "inf/tau";
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
    if (singular_.count() > 0) {
      std::string where;
      for (const auto& p : singular_.paths()) where += "\n//       " + p;
      d << "//   - removable singularities (x/(exp(x)-1) forms, 0/0 where x = 0) rewritten with exprel(): "
        << singular_.count() << ", at" << where << "\n";
      notes_.push_back("removable singularities rewritten with exprel(): " + std::to_string(singular_.count()));
    }
    d << "#include <cmath>\n#include <limits>\n#include <type_traits>\n\n"
      << "#include \"cellml/cellml_math.hpp\"\n#include \"model/block_access.hpp\"\n#include \"model/cell_model.hpp\"\n\n"
      << "namespace {\n\nFIBRODEM_USE_LANE_MATH;\nusing namespace fibrodem::cellml_math;\n\n";
    d << "enum State {";
    for (int q : m_.states) d << " kS_" << ident_[q] << ",";
    d << " kNumStates };\nenum Param {";
    for (int q : params) d << " kP_" << ident_[q] << ",";
    if (!o_.myofilament && b_.c_param < 0) d << " kP_C_pF,";
    d << " kNumParams };\n";
    d << (o_.myofilament ? "enum Input { kIn_Ca_i };\n" : "enum Input { kIn_i_ext };\n");
    d << "enum Output {" << (o_.myofilament ? "" : " kOut_I_ion,");
    for (const auto& [signal, q] : b_.mapped)
      if (!(signal == "Ca_i" && o_.myofilament)) d << " kOut_" << sanitize(signal) << ",";
    d << " kNumOutputs };\n\n";
    d << "class " << class_name() << " final : public fibrodem::CellModel {\n public:\n  " << class_name() << "() {\n"
      << "    info_.name = \"" << o_.name << "\";\n    info_.version = \"1.0.0\";\n"
      << "    info_.description = \"Imported from CellML " << m_.doc.version << " model '" << m_.doc.model_name << "'."
      << (b_.summary.empty() ? "" : " " + b_.summary + ".") << "\";\n"
      << "    info_.reference = \"" << o_.source_name << "\";\n"
      << "    info_.kind = fibrodem::ModelKind::" << (o_.myofilament ? "myofilament" : "ionic") << ";\n"
      << "    info_.states = {\n";
    for (int q : m_.states) {
      const GateForm& g = gates_[q];
      double lower = -1e300, upper = 1e300, initial = m_.quantities[q].initial;
      if (q == b_.v) {
        lower = -500.0;
        upper = 500.0;
        initial *= b_.v_scale;
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
    if (!o_.myofilament && b_.c_param < 0)
      d << "        {\"C_pF\", \"pF\", " << lit(b_.capacitance_pF) << ", \"membrane capacitance: i_ext / C_pF enters dV/dt"
        << (b_.area_note.empty() ? "" : " (C_pF = specific capacitance x membrane area)") << "\"},\n";
    d << "    };\n";
    if (o_.myofilament)
      d << "    info_.inputs = {{\"Ca_i\", \"mM\", \"cytosolic Ca2+ of the host myocyte\"}};\n";
    else
      d << "    info_.inputs = {{\"i_ext\", \"pA\", \"stimulus and gap-junction current, + depolarising\"}};\n";
    d << "    info_.outputs = {\n";
    if (!o_.myofilament) d << "        {\"I_ion\", \"pA\", \"total ionic current, + outward (i_ext - C dV/dt)\"},\n";
    for (const auto& [signal, q] : b_.mapped)
      if (!(signal == "Ca_i" && o_.myofilament))
        d << "        {\"" << signal << "\", \"" << output_unit(signal, q) << "\", \"CellML " << m_.source(q).qualified()
          << "\"},\n";
    d << "    };\n";
    if (!o_.myofilament) {
      int vk = 0;
      for (std::size_t k = 0; k < m_.states.size(); ++k)
        if (m_.states[k] == b_.v) vk = static_cast<int>(k);
      d << "    info_.voltage_state = " << vk << ";\n    info_.capacitance_parameter = kP_"
        << (b_.c_param >= 0 ? ident_[b_.c_param] : std::string("C_pF")) << ";\n";
    }
    d << "  }\n\n  const fibrodem::ModelInfo& info() const override { return info_; }\n\n";
    return d.str();
  }

  std::string cmake() const {
    return "# The plugin " + o_.name + ", generated by `fibrodem import-cellml` from " + o_.source_name + ".\n"
           "# Build it with an installed fibrodem (its SDK):\n"
           "#   cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=/where/fibrodem/is/installed && cmake --build build\n"
           "cmake_minimum_required(VERSION 3.20)\n"
           "project(fibrodem_plugin_" + o_.name + " LANGUAGES CXX)\n"
           "find_package(fibrodem REQUIRED)\n"
           "fibrodem_add_cell_model(" + o_.name + " " + o_.name + ".cpp)\n";
  }


  const Model& m_;
  const WriterOptions& o_;
  const InterfaceMap b_;
  std::vector<std::string> notes_;
  std::vector<bool> lane_, timed_, needed_;
  std::vector<GateForm> gates_;
  const std::vector<std::string> ident_;
  ExpressionWriter expr_;
  Singularities singular_;
};

}  // namespace

GeneratedPlugin write_plugin(const Model& model, const WriterOptions& options) {
  return Writer(model, options).run();
}

}  // namespace fibrodem::cellml
