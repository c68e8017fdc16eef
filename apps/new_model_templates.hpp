// The files `fibrodem new-model` writes: a plugin's source, its
// CMakeLists.txt (out of tree, against an installed fibrodem) and a test
// manifest, per kind. @NAME@ is the plugin's name, @CLASS@ its class name.
#pragma once

namespace fibrodem::cli::templates {

inline constexpr const char* kCMakeLists = R"TPL(# Builds the @KIND@ plugin `@NAME@` out of the fibrodem tree, against an
# installed fibrodem (its plugin SDK: headers only, nothing to link):
#
#   cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=<fibrodem's install prefix>
#   cmake --build build
#   ctest --test-dir build          # runs @NAME@_test.json with the plugin
#   FIBRODEM_PLUGIN_PATH=$PWD/build fibrodem run @NAME@_test.json
#   cmake --install build --prefix <fibrodem's install prefix>   # optional:
#                                   # then fibrodem finds it without the path
# Without a build type, fibrodem's CMake package chooses Release; Debug or
# RelWithDebInfo build for a debugger (docs/dev/build_types.md in fibrodem).
cmake_minimum_required(VERSION 3.20)
project(@NAME@ LANGUAGES CXX)

find_package(fibrodem REQUIRED)
@ADD_FUNCTION@(@NAME@ @NAME@.cpp)

# `ctest`: the test manifest runs to completion with this plugin found first.
enable_testing()
add_test(NAME @NAME@_runs
         COMMAND ${FIBRODEM_EXECUTABLE} run ${CMAKE_CURRENT_SOURCE_DIR}/@NAME@_test.json
                 --out ${CMAKE_CURRENT_BINARY_DIR}/test_run --overwrite --quiet)
set_tests_properties(@NAME@_runs PROPERTIES ENVIRONMENT "FIBRODEM_PLUGIN_PATH=$<TARGET_FILE_DIR:@TARGET@>")
)TPL";

// ---- ionic ------------------------------------------------------------------

inline constexpr const char* kIonicSource = R"TPL(// @NAME@: a cell-model plugin for fibrodem (ionic), written by
// `fibrodem new-model`. A starting point: a fibroblast-like membrane with a
// linear leak and one voltage-gated K+ current,
//   C dV/dt = i_ext - I_leak - I_K
//   I_leak = g_leak (V - E_leak),  I_K = g_K n (V - E_K)
//   dn/dt = (n_inf(V) - n) / tau_n
// Replace the equations, states and parameters with your model's; say in
// `reference` where they come from. Units: mV, ms, pA, pF, nS (nS x mV = pA,
// pA / pF = mV/ms). fibrodem's docs/guide/plugins.md ("Writing a cell-model
// plugin") has the whole contract; check the plugin with
// `fibrodem check-plugin` after building.
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {

FIBRODEM_USE_LANE_MATH;  // exp, log, pow, select, ... for SIMD lanes and double alike

// Indices into the lists declared in the constructor, in the same order.
enum State { kV, kn };
enum Param { kC_pF, kg_leak_nS, kE_leak_mV, kg_K_nS, kE_K_mV, ktau_n_ms };
enum Input { kI_ext_pA };
enum Output { kI_ion_pA };

class @CLASS@ final : public fibrodem::CellModel {
 public:
  @CLASS@() {
    info_.name = "@NAME@";  // must equal the plugin's name (libfibrodem_@NAME@.so)
    info_.version = "0.1.0";
    info_.description = "Leak + one gated K+ current (new-model skeleton)";
    info_.reference = "none yet: cite the paper of your equations here";
    info_.kind = fibrodem::ModelKind::ionic;
    // name, unit, initial value, physical bounds (leaving them stops the run),
    // gate (Rush-Larsen integrates it exactly), voltage_only (its rates depend
    // on V alone: fibrodem may tabulate them).
    info_.states = {
        {"V", "mV", -50.0, -200.0, 100.0, false},
        {"n", "1", 0.05, 0.0, 1.0, true, true},
    };
    // name, unit, default, description; a manifest may set any of them.
    info_.parameters = {
        {"C_pF", "pF", 6.3, "membrane capacitance"},
        {"g_leak_nS", "nS", 0.1, "leak conductance"},
        {"E_leak_mV", "mV", -40.0, "leak reversal potential"},
        {"g_K_nS", "nS", 1.0, "K+ conductance"},
        {"E_K_mV", "mV", -87.0, "K+ reversal potential"},
        {"tau_n_ms", "ms", 20.0, "time constant of the K+ gate"},
    };
    // An ionic model's first input is i_ext (stimulus + gap junctions) and
    // its first output I_ion.
    info_.inputs = {{"i_ext", "pA", "stimulus and gap-junction current, + depolarising"}};
    info_.outputs = {{"I_ion", "pA", "total ionic current, + outward"}};
    info_.voltage_state = kV;
    info_.capacitance_parameter = kC_pF;
    // Optional named parameter sets (the first is the default):
    // info_.variants = {{"fast_K", "tau_n 5 ms", {{"tau_n_ms", 5.0}}, {}}};
  }

  const fibrodem::ModelInfo& info() const override { return info_; }

  // Every state's derivative in the linear form dy/dt = a + b y, for the
  // cells of the block, 8 (AVX-512) or 4 (AVX2) at a time. No allocation,
  // exception or look-up by name in here: it runs for every block and step.
  void evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const override {
    const double C = block.params[kC_pF];
    const double g_leak = block.params[kg_leak_nS], E_leak = block.params[kE_leak_mV];
    const double g_K = block.params[kg_K_nS], E_K = block.params[kE_K_mV];
    const double tau_n = block.params[ktau_n_ms];
    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using R = typename std::decay_t<decltype(cell)>::Real;  // SIMD lanes, or double
      const R V = cell.state(kV);
      // A branch on a cell's value is select(condition, a, b), not `if`.
      const R n_inf = 1.0 / (1.0 + exp(-(V + 20.0) / 9.0));
      if (!block.skip_voltage_only_gates) cell.gate_inf_tau(kn, n_inf, R(tau_n));
      const R I_leak = g_leak * (V - E_leak);
      const R I_K = g_K * cell.state(kn) * (V - E_K);
      const R I_ion = I_leak + I_K;
      cell.rate(kV, (cell.input(kI_ext_pA) - I_ion) / C);
      cell.output(kI_ion_pA, I_ion);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};

}  // namespace

// Exports the plugin ABI version and the factory fibrodem calls.
FIBRODEM_CELL_MODEL_PLUGIN(@CLASS@)
)TPL";

inline constexpr const char* kIonicManifest = R"TPL({
  "fibrodem": 1,
  "name": "@NAME@_test",
  "seed": 1,
  "duration_ms": 1000,
  "tissue": { "builder": "single_cell", "type": "fibroblast" },
  "cells": { "fibroblast": { "model": "@NAME@" } },
  "stimulus": [
    { "target": "fibroblast", "start_ms": 100, "duration_ms": 2, "amplitude_pA": 50, "period_ms": 500, "count": 2 }
  ],
  "solver": { "method": "rush_larsen", "dt_ms": 0.01 },
  "output": {
    "traces": { "cells": [0], "variables": ["V", "n", "I_ion"], "every_ms": 0.5 }
  }
}
)TPL";

// ---- myofilament ------------------------------------------------------------

inline constexpr const char* kMyofilamentSource = R"TPL(// @NAME@: a myofilament plugin for fibrodem, written by `fibrodem
// new-model`. A starting point: one activation state A driven by the host
// myocyte's cytosolic Ca (Hill binding), and an unloaded cell that shortens
// in proportion to it,
//   dA/dt = k_on f(Ca) (1 - A) - k_off A,   f = Ca^h / (Ca^h + Ca50^h)
//   active_tension = A,   sarcomere_length = SL_rest (1 - shortening_max A)
// Replace them with your model's (e.g. a cross-bridge model). A myofilament
// model reads exactly one input, Ca_i [mM], and must output sarcomere_length
// [um] (the DEM mechanics take the cell's length from it). Units: ms, mM, um.
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {

FIBRODEM_USE_LANE_MATH;  // exp, log, pow, select, ... for SIMD lanes and double alike

enum State { kA };
enum Param { kk_on, kk_off, kCa50_mM, kHill, kSL_rest_um, kShortening_max };
enum Input { kCa_i_mM };
enum Output { kSL_um, kTension };

class @CLASS@ final : public fibrodem::CellModel {
 public:
  @CLASS@() {
    info_.name = "@NAME@";  // must equal the plugin's name (libfibrodem_@NAME@.so)
    info_.version = "0.1.0";
    info_.description = "One Ca-driven activation state (new-model skeleton)";
    info_.reference = "none yet: cite the paper of your equations here";
    info_.kind = fibrodem::ModelKind::myofilament;
    // name, unit, initial value, physical bounds, gate (Rush-Larsen exact).
    info_.states = {{"A", "1", 0.0, 0.0, 1.0, true}};
    info_.parameters = {
        {"k_on", "1/ms", 0.1, "activation rate at saturating Ca"},
        {"k_off", "1/ms", 0.02, "relaxation rate"},
        {"Ca50_mM", "mM", 0.0006, "Ca of half activation"},
        {"hill", "1", 3.0, "Hill coefficient of Ca binding"},
        {"SL_rest_um", "um", 1.9, "sarcomere length at rest"},
        {"shortening_max", "1", 0.15, "fractional shortening at full activation"},
    };
    info_.inputs = {{"Ca_i", "mM", "bulk cytosolic Ca of the host myocyte"}};
    info_.outputs = {
        {"sarcomere_length", "um", "sarcomere length"},
        {"active_tension", "1", "normalised active tension"},
    };
    // A myofilament model has no membrane potential or capacitance.
    info_.voltage_state = -1;
    info_.capacitance_parameter = -1;
  }

  const fibrodem::ModelInfo& info() const override { return info_; }

  void evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const override {
    const double k_on = block.params[kk_on], k_off = block.params[kk_off];
    const double Ca50_h = std::pow(block.params[kCa50_mM], block.params[kHill]);
    const double hill = block.params[kHill];
    const double SL_rest = block.params[kSL_rest_um], shortening = block.params[kShortening_max];
    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using R = typename std::decay_t<decltype(cell)>::Real;  // SIMD lanes, or double
      const R Ca = fmax(cell.input(kCa_i_mM), R(0.0));
      const R Ca_h = pow(Ca, hill);
      const R f = Ca_h / (Ca_h + Ca50_h);
      // dA/dt = alpha (1 - A) - beta A: a gate, integrated exactly.
      cell.gate_alpha_beta(kA, k_on * f, R(k_off));
      const R A = cell.state(kA);
      cell.output(kSL_um, SL_rest * (1.0 - shortening * A));
      cell.output(kTension, A);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};

}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(@CLASS@)
)TPL";

inline constexpr const char* kMyofilamentManifest = R"TPL({
  "fibrodem": 1,
  "name": "@NAME@_test",
  "seed": 1,
  "duration_ms": 600,
  "effects": ["electrophysiology", "contraction"],
  "tissue": { "builder": "single_cell", "type": "myocyte" },
  "cells": { "myocyte": { "model": "colman", "myofilament": "@NAME@" } },
  "stimulus": [
    { "target": "myocyte", "start_ms": 50, "duration_ms": 2, "amplitude_pA": 2000, "period_ms": 1000, "count": 1 }
  ],
  "solver": { "method": "rush_larsen", "dt_ms": 0.01 },
  "output": {
    "traces": { "cells": [0], "variables": ["V", "Ca_i", "sarcomere_length", "active_tension"], "every_ms": 1 }
  }
}
)TPL";

// ---- contact law ------------------------------------------------------------

inline constexpr const char* kContactLawSource = R"TPL(// @NAME@: a contact-law plugin for fibrodem's DEM mechanics, written by
// `fibrodem new-model`. A starting point: Hertz-type normal contact in
// compression, a linear bond in tension (while intact), a linear shear spring
// and a normal dashpot:
//   overlap d = ref_gap - gap (> 0: pressed together)
//   d > 0:            F_n = kn d0 (d / d0)^(3/2)   (Hertz: F ~ d^(3/2); equal
//                                                   to the linear spring at d0)
//   d < 0, intact:    F_n = kn d                   (bond in tension)
//   F_s -= ks ds      (incremental, while intact or pressed)
//   F_n total = F_n - c_n dn/dt,  c_n = 2 beta sqrt(m_eff kn)
// kn, ks are the manifest's mechanics.kn_N_per_m, ks_N_per_m (per contact,
// after the fibroblast factor). Replace with your law; fibrodem's
// docs/guide/plugins.md ("Contact-law plugins") describes the contract
// (mechanics/contact_law_plugin.hpp).
// Units: SI (m, N, kg, s).
#include <cmath>
#include <cstdint>

#include "mechanics/contact_law_plugin.hpp"

namespace {

enum Param { kReferenceOverlap_um, kDampingRatio, kMaxOverlap_um };

class @CLASS@ final : public fibrodem::ContactLaw {
 public:
  @CLASS@() {
    info_.name = "@NAME@";  // must equal the plugin's name (libfibrodem_contact_law_@NAME@.so)
    info_.version = "0.1.0";
    info_.description = "Hertz-type compression, linear bond in tension (new-model skeleton)";
    info_.reference = "Hertz contact: Johnson, Contact Mechanics (1985), ch. 4";
    // Set from the manifest's mechanics.contact_law_parameters (by name).
    info_.parameters = {
        {"reference_overlap_um", "um", 1.0, "d0: overlap at which the Hertz force equals kn d0"},
        {"damping_ratio", "1", 0.1, "normal dashpot as a fraction of critical damping"},
        {"max_overlap_um", "um", 4.0, "largest overlap expected: sets the stable step (tangent stiffness there)"},
    };
  }

  const fibrodem::ContactLawInfo& info() const override { return info_; }

  // Per-contact constants, once kn, ks and m_eff are known.
  void prepare(fibrodem::BondSet& b, const double* params) const override {
    for (std::size_t i = 0; i < b.size(); ++i) b.cn[i] = 2 * params[kDampingRatio] * std::sqrt(b.m_eff[i] * b.kn[i]);
  }

  // One block of contacts: plain loops over arrays (no call per contact).
  void update(fibrodem::BondSet& b, const fibrodem::BondBlock& blk, const double* params,
              double dt_s) const override {
    const double d0 = params[kReferenceOverlap_um] * 1e-6;
    const double inv_dt = 1 / dt_s;
    for (std::size_t j = 0; j < blk.count; ++j) {
      const std::size_t i = blk.begin + j;  // index into the BondSet
      const double d = b.ref_gap[i] - blk.gap[j];
      const bool pressed = d > 0;
      const bool acting = pressed || b.intact[i];
      const double fn = pressed ? b.kn[i] * d0 * std::pow(d / d0, 1.5) : acting ? b.kn[i] * d : 0.0;
      const double fs = acting ? b.fs[i] - b.ks[i] * blk.ds[j] : 0.0;
      b.fn[i] = fn;
      b.fs[i] = fs;
      blk.fn_total[j] = acting ? fn - b.cn[i] * blk.dn[j] * inv_dt : 0.0;
      blk.fs_total[j] = fs;
    }
  }

  // Hertz's tangent stiffness grows as sqrt(d): 1.5 kn sqrt(d/d0) at the
  // largest overlap expected sets the stable step, with the dashpot's margin.
  double stable_step_stiffness(double k, bool shear, const double* params) const override {
    if (shear) return k;
    const double tangent = std::fmax(1.0, 1.5 * std::sqrt(params[kMaxOverlap_um] / params[kReferenceOverlap_um]));
    const double beta = params[kDampingRatio];
    const double f = std::sqrt(1 + beta * beta) - beta;
    return k * tangent / (f * f);
  }

 private:
  fibrodem::ContactLawInfo info_;
};

}  // namespace

// Exports the contact-law ABI version and the factory fibrodem calls.
FIBRODEM_CONTACT_LAW_PLUGIN(@CLASS@)
)TPL";

inline constexpr const char* kContactLawManifest = R"TPL({
  "fibrodem": 1,
  "name": "@NAME@_test",
  "seed": 1,
  "duration_ms": 400,
  "effects": ["electrophysiology", "coupling", "mechanics"],
  "tissue": { "builder": "cell_pair", "fibroblasts": 2 },
  "cells": {
    "myocyte": { "model": "colman", "myofilament": "rice" },
    "fibroblast": { "model": "passive_fibroblast" }
  },
  "coupling": { "law": "gap_junction", "D_f_nS": 0.5 },
  "stimulus": [
    { "target": "myocyte", "start_ms": 20, "duration_ms": 2, "amplitude_pA": 2000 }
  ],
  "solver": { "method": "rush_larsen", "dt_ms": 0.01 },
  "mechanics": {
    "contact_law": "@NAME@",
    "contact_law_parameters": { "reference_overlap_um": 1.0, "damping_ratio": 0.1 }
  },
  "output": {
    "traces": { "cells": [0], "variables": ["V", "sarcomere_length"], "every_ms": 1 }
  }
}
)TPL";

}  // namespace fibrodem::cli::templates
