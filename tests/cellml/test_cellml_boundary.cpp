// `fibrodem import-cellml` at fibrodem's boundary: which state is V and which
// quantity is the CellML's stimulus (annotation, then name, then structure),
// and the stimulus replaced by i_ext wherever the model uses it. The models
// are written for these tests (tests/cellml); every expected number is
// computed here from the equations and constants their comments state.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <unistd.h>

#include "cellml/import.hpp"
#include "cellml/import_error.hpp"
#include "model/plugin_registry.hpp"
#include "support/cellml_plugins.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

namespace {

using testing::evaluate;
using testing::index_of;
using testing::kCellml;
using testing::kGenerated;
using testing::load;
using testing::output_of;
using testing::rk4;
using testing::without_origin;

cellml::ImportResult import(const std::string& file, const std::string& name,
                            const std::function<void(cellml::ImportOptions&)>& edit = {}) {
  cellml::ImportOptions o;
  o.input = kCellml / file;
  o.name = name;
  o.out = fs::temp_directory_path() / ("fibrodem_cellml_boundary_" + std::to_string(::getpid())) / name;
  o.overwrite = true;
  if (edit) edit(o);
  return cellml::import_cellml(o);
}

std::string all_notes(const cellml::ImportResult& r) {
  std::string s;
  for (const auto& n : r.notes) s += n + "\n";
  return s;
}

std::string source_of(const cellml::ImportResult& r, const std::string& name) {
  return testing::read_file(r.folder / (name + ".cpp"));
}

// tests/cellml/lumped_stimulus_*.cellml, by hand: i_tot = i_L + i_stim, dV/dt = -i_tot / Cm,
// dK_i/dt = -(i_L + i_stim) / (F vol), i_L = g_L (V - RTF ln(K_o / K_i)); fibrodem's i_ext
// (+ depolarising) is i_stim = -i_ext, since this model's stimulus depolarises when negative.
constexpr double kCm_pF = 50, kG_nS = 2, kRTF_mV = 26.7, kKo_mM = 5.4, kF = 96485, kVol_pL = 2;
std::array<double, 2> lumped_rates(double V, double K_i, double i_ext) {
  const double i_L = kG_nS * (V - kRTF_mV * std::log(kKo_mM / K_i));
  const double i_stim = -i_ext;
  return {-(i_L + i_stim) / kCm_pF, -(i_L + i_stim) / (kF * kVol_pL)};  // mV/ms; pA/(C/mol pL) = mM/ms
}

}  // namespace

TEST_CASE("import-cellml: a stimulus lumped into an ionic current becomes i_ext there and in dK_i/dt") {
  auto model = load("cellml_lumped");
  const auto& info = model->info();
  const int kV = index_of(info.states, "V"), kK = index_of(info.states, "K_i");
  CHECK(info.voltage_state == kV);
  CHECK(info.parameters[info.capacitance_parameter].name == "Cm");
  CHECK(info.parameters[info.capacitance_parameter].default_value == 50.0);
  const int seen = output_of(info, "i_stim_seen"), i_ion = output_of(info, "I_ion");
  for (bool lanes : {false, true})
    // t = 10.5 ms lies in the CellML's own pulse (10 to 11 ms, -800 pA): the plugin must ignore it.
    for (double t : {0.0, 10.5})
      for (double i_ext : {0.0, 350.0, -120.0})
        for (const auto& state : {std::pair{-85.0, 140.0}, std::pair{-20.0, 120.0}}) {
          // Named copies, not a structured binding: INFO's lambda may not capture one (clang 14).
          const double V = state.first, K_i = state.second;
          const auto r = evaluate(*model, {V, K_i}, t, i_ext, lanes);
          const auto expected = lumped_rates(V, K_i, i_ext);
          INFO("lanes " << lanes << " t " << t << " i_ext " << i_ext << " V " << V << " K_i " << K_i);
          CHECK(r.dydt[kV] == doctest::Approx(expected[0]).epsilon(1e-12));
          CHECK(r.dydt[kK] == doctest::Approx(expected[1]).epsilon(1e-12));
          // --map on the stimulus traces it as the model sees it, in pA.
          CHECK(r.outputs[seen] == doctest::Approx(-i_ext).epsilon(1e-15));
          // I_ion = i_ext - C dV/dt is the leak alone: the stimulus does not leak into it.
          CHECK(r.outputs[i_ion] == doctest::Approx(kG_nS * (V - kRTF_mV * std::log(kKo_mM / K_i))).epsilon(1e-9));
        }
}

TEST_CASE("import-cellml: the lumped model paced by i_ext follows its equations integrated by hand") {
  // A 1 ms, 800 pA pulse at 10 ms through fibrodem's input, 40 ms by RK4 (dt 0.01 ms) on the plugin
  // and on lumped_rates(); the same method on the same equations: round-off apart.
  auto model = load("cellml_lumped");
  auto i_ext = [](double t) { return t >= 10.0 && t < 11.0 ? 800.0 : 0.0; };
  std::array<double, 2> ref{-85.0, 140.0};
  std::vector<double> y{-85.0, 140.0};
  auto f_ref = [&](double t, const std::array<double, 2>& s) { return lumped_rates(s[0], s[1], i_ext(t)); };
  auto f_plugin = [&](double t, const std::array<double, 2>& s) {
    const auto r = evaluate(*model, {s[0], s[1]}, t, i_ext(t), true);
    return std::array<double, 2>{r.dydt[0], r.dydt[1]};
  };
  std::array<double, 2> plugin{-85.0, 140.0};
  double peak = -100;
  for (int i = 0; i < 4000; ++i) {
    rk4(ref, i * 0.01, 0.01, f_ref);
    rk4(plugin, i * 0.01, 0.01, f_plugin);
    peak = std::max(peak, plugin[0]);
  }
  CHECK(plugin[0] == doctest::Approx(ref[0]).epsilon(1e-12));
  CHECK(plugin[1] == doctest::Approx(ref[1]).epsilon(1e-12));
  // The pulse moved V: 800 pA / 50 pF over 1 ms, less the leak (tau = Cm / g_L = 25 ms): ~15 mV.
  CHECK(peak > -85.0 + 10.0);
}

TEST_CASE("import-cellml: the notes name the stimulus, the rule that chose it and every place it is used") {
  for (const std::string version : {"1_0", "1_1", "2_0"}) {
    const auto r = import("lumped_stimulus_" + version + ".cellml", "lumped");
    const std::string notes = all_notes(r);
    INFO(notes);
    CHECK(notes.find("V: membrane.V [mV] is the membrane potential (rule: name: V)") != std::string::npos);
    CHECK(notes.find("stimulus: stimulus.i_stim [pA] (rule: name: i_stim) is fibrodem's input i_ext") !=
          std::string::npos);
    CHECK(notes.find("wherever it is used (membrane.i_tot, d(potassium.K_i)/dt): i_stim = i_ext * (-1.0)") !=
          std::string::npos);
    // The header of the generated source and the description run.log prints carry the choice.
    const std::string cpp = source_of(r, "lumped");
    CHECK(cpp.find("//   - stimulus: stimulus.i_stim [pA] (rule: name: i_stim)") != std::string::npos);
    CHECK(cpp.find("stimulus: stimulus.i_stim (name: i_stim) replaced by i_ext.\";") != std::string::npos);
  }
}

TEST_CASE("import-cellml: oxmeta annotations choose V and the stimulus where the names would mislead") {
  // tests/cellml/oxmeta_annotated_*.cellml: u is the potential (cmeta:id / id membrane_voltage), V a
  // filtered copy (dV/dt = (u - V) / 5 ms), i_pulse the stimulus (RDF membrane_stimulus_current),
  // i_stim a 3 pA holding current; du/dt = -(1 nS (u + 80 mV) + 3 pA + i_pulse) / 20 pF.
  auto model = load("cellml_oxmeta");
  const auto& info = model->info();
  const int kU = index_of(info.states, "V"), kFiltered = index_of(info.states, "membrane_V");
  CHECK(info.voltage_state == kU);
  std::vector<double> y(2);
  y[kU] = -60.0;
  y[kFiltered] = -75.0;
  for (bool lanes : {false, true})
    for (double i_ext : {0.0, 400.0}) {
      // t = 5.5 ms is inside the file's own pulse (5 to 6 ms, -400 pA): ignored.
      const auto r = evaluate(*model, y, 5.5, i_ext, lanes);
      const double expected = -(1.0 * (-60.0 + 80.0) + 3.0 - i_ext) / 20.0;  // -1.15 and 18.85 mV/ms
      CHECK(r.dydt[kU] == doctest::Approx(expected).epsilon(1e-12));
      CHECK(r.dydt[kFiltered] == doctest::Approx((-60.0 + 75.0) / 5.0).epsilon(1e-12));
    }
  // CellML 1.0 (cmeta:id) and 2.0 (id) annotate alike and give the same plugin.
  const auto r10 = import("oxmeta_annotated_1_0.cellml", "oxmeta");
  const auto r20 = import("oxmeta_annotated_2_0.cellml", "oxmeta");
  CHECK(without_origin(source_of(r10, "oxmeta")) == without_origin(source_of(r20, "oxmeta")));
  const std::string notes = all_notes(r20);
  CHECK(notes.find("membrane.u [mV] is the membrane potential (rule: annotation: oxmeta membrane_voltage)") !=
        std::string::npos);
  CHECK(notes.find("membrane.i_pulse [pA] (rule: annotation: oxmeta membrane_stimulus_current)") !=
        std::string::npos);
}

TEST_CASE("import-cellml: --voltage and --stimulus override the annotations, and a state-dependent stimulus is refused") {
  const auto r = import("oxmeta_annotated_1_0.cellml", "overridden", [](cellml::ImportOptions& o) {
    o.voltage = "membrane.u";
    o.stimulus = "membrane.i_stim";
  });
  const std::string notes = all_notes(r);
  CHECK(notes.find("membrane.u [mV] is the membrane potential (rule: --voltage)") != std::string::npos);
  CHECK(notes.find("membrane.i_stim [pA] (rule: --stimulus)") != std::string::npos);
  // The annotated pulse is then an ordinary current of the model: its protocol stays.
  CHECK(source_of(r, "overridden").find("pulse_amplitude") != std::string::npos);
  try {
    import("oxmeta_annotated_1_0.cellml", "refused", [](cellml::ImportOptions& o) { o.stimulus = "membrane.i_leak"; });
    FAIL("a stimulus that depends on a state was accepted");
  } catch (const cellml::ImportError& e) {
    CHECK(std::string(e.what()).find("the stimulus membrane.i_leak (--stimulus) depends on the state membrane.u") !=
          std::string::npos);
  }
}

TEST_CASE("import-cellml: a model whose potential is Vm runs from a manifest tracing V") {
  // tests/cellml/vm_named_2_0.cellml: per membrane area, Cm 1 uF/cm^2, g 0.1 mS/cm^2, E -70 mV; its
  // stimulus pulse_current is found by structure. Default C_pF 100 pF (1e-4 cm^2): a 1000 pA pulse
  // of 2 ms from 10 ms gives V = E + (I / C) tau (1 - exp(-2 / tau)) at 12 ms, I / C = 10 mV/ms,
  // tau = Cm / g = 10 ms: -70 + 18.127 mV.
  json m = json::parse(R"({
    "fibrodem": 1, "name": "vm_named", "duration_ms": 20,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "cellml_vm"}},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 1000}],
    "solver": {"method": "euler", "dt_ms": 0.001},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
  m["plugin_path"] = kGenerated.string();
  const fs::path dir = testing::scratch_dir("cellml_vm_named");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  const auto& times = sim.trace_times();
  const auto& V = sim.trace("V", 0);
  double at_12 = std::nan("");
  for (std::size_t k = 0; k < times.size(); ++k)
    if (std::fabs(times[k] - 12.0) < 1e-9) at_12 = V[k];
  const double expected = -70.0 + 10.0 * 10.0 * (1.0 - std::exp(-0.2));
  CHECK(at_12 == doctest::Approx(expected).epsilon(1e-3));  // forward Euler at dt/tau 1e-4: ~1e-4 relative
  CHECK(V.front() == -70.0);
  const std::string log = testing::read_file(dir / "run.log");
  CHECK(log.find("model cellml_vm: Imported from CellML 2.0 model 'vm_named'. V: cell.Vm (name: Vm); stimulus: "
                 "cell.pulse_current (structure: a current of time and constants alone in dV/dt) replaced by i_ext.") !=
        std::string::npos);
}

TEST_CASE("import-cellml: of a chain of currents named as the stimulus, the one dV/dt uses is taken") {
  // tests/cellml/stimulus_chain_1_1.cellml: membrane.i_Stim = stimulus_protocol.Istim, both stimulus
  // names. By hand at V0 -80 mV (C 20 pF, g 1 nS, E -85 mV): g (V - E) = 5 pA; dV/dt = -5/20 = -0.25 mV/ms
  // with i_ext 0, -(5 - 100)/20 = 4.75 mV/ms with i_ext 100 pA (i_Stim = -i_ext), also at t = 10.5 ms,
  // inside the CellML's own -800 pA pulse, which the plugin leaves out.
  const auto r = import("stimulus_chain_1_1.cellml", "stimulus_chain");
  const std::string notes = all_notes(r);
  INFO(notes);
  CHECK(notes.find("stimulus: membrane.i_Stim [pA] (rule: name: i_Stim) is fibrodem's input i_ext") != std::string::npos);
  CHECK(notes.find("the CellML's membrane.C [pF] is the capacitance parameter") != std::string::npos);
  const auto plugin = load("cellml_stimulus_chain");  // the same file, imported at build time
  for (double t : {0.0, 10.5}) {
    CHECK(evaluate(*plugin, {-80.0}, t, 0.0, false).dydt[0] == doctest::Approx(-0.25).epsilon(1e-12));
    CHECK(evaluate(*plugin, {-80.0}, t, 100.0, false).dydt[0] == doctest::Approx(4.75).epsilon(1e-12));
  }
}
