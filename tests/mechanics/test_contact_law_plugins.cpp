// Contact laws as plugins: the bundled laws give the forces the core's own
// code gave before they were plugins, bit for bit; a law built out of tree
// (tests/plugins/hertz_normal.cpp, SDK only) loads and follows its formula;
// parameters are set by name from the manifest and unknown names refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <cstdint>
#include <cstdlib>
#include <random>

#include "mechanics/contact_law.hpp"
#include "mechanics/dem_spec.hpp"
#include "model/plugin_registry.hpp"
#include "run/simulation.hpp"
#include "util/json_reader.hpp"
#include "scene/scene.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

const std::string kTestPlugins = std::string(FIBRODEM_BINARY_DIR) + "/test_plugins";

// linear_bond's update as the core computed it before laws were plugins
// (core/mechanics/contact_laws/linear_bond.cpp at commit 29a51d6), frozen
// here as the reference the plugin must match bit for bit.
void frozen_linear_bond_update(BondSet& b, const BondBlock& blk, double dt, double tensile_, double shear_,
                               double mu_) {
  const double inv_dt = 1 / dt;
  double* const fn = b.fn.data() + blk.begin;
  double* const fs = b.fs.data() + blk.begin;
  const double* const kn = b.kn.data() + blk.begin;
  const double* const ks = b.ks.data() + blk.begin;
  const double* const cn = b.cn.data() + blk.begin;
  const double* const cs = b.cs.data() + blk.begin;
  const double* const ref = b.ref_gap.data() + blk.begin;
  std::uint8_t* const intact = b.intact.data() + blk.begin;
  for (std::size_t i = 0; i < blk.count; ++i) {
    const double overlap = ref[i] - blk.gap[i];
    if (intact[i]) {
      double n = kn[i] * overlap;
      double s = fs[i] - ks[i] * blk.ds[i];
      if (-n >= tensile_) {
        intact[i] = 0;
        n = 0;
        s = 0;
      } else if (std::abs(s) >= shear_) {
        intact[i] = 0;
        const double cap = n > 0 ? mu_ * n : 0.0;
        if (std::abs(s) > cap) s = std::copysign(cap, s);
      }
      fn[i] = n;
      fs[i] = s;
      blk.fn_total[i] = n - cn[i] * blk.dn[i] * inv_dt;
      blk.fs_total[i] = s - cs[i] * blk.ds[i] * inv_dt;
    } else if (overlap >= 0) {
      const double n = kn[i] * overlap;
      double s = fs[i] - ks[i] * blk.ds[i];
      const double cap = mu_ * n;
      if (std::abs(s) > cap) s = std::copysign(cap, s);
      fn[i] = n;
      fs[i] = s;
      blk.fn_total[i] = n - cn[i] * blk.dn[i] * inv_dt;
      blk.fs_total[i] = s - cs[i] * blk.ds[i] * inv_dt;
    } else {
      fn[i] = 0;
      fs[i] = 0;
      blk.fn_total[i] = 0;
      blk.fs_total[i] = 0;
    }
  }
}

// Contacts of the sizes of the paper's tissue (kn ~ 26 N/m, gaps ~ 0.1 um),
// bonded and not, with shear histories that reach the strengths below.
BondSet random_contacts(std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  BondSet b;
  b.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    b.p[i] = static_cast<int>(i);
    b.q[i] = static_cast<int>(i + 1);
    b.kn[i] = 26 * (1.25 + u(rng));
    b.ks[i] = 0.26 * (1.25 + u(rng));
    b.m_eff[i] = 1e-10 * (1.5 + u(rng));
    b.ref_gap[i] = 0.2e-6 * (1 + u(rng));
    b.kb[i] = 1e-9 * (1 + u(rng));
    b.fs[i] = 2e-7 * u(rng);
    b.mb[i] = 1e-12 * u(rng);
    b.intact[i] = u(rng) > -0.5 ? 1 : 0;
  }
  return b;
}

struct Kinematics {
  std::vector<double> gap, dn, ds, dth, fn, fs, mt;
  explicit Kinematics(std::size_t n) : gap(n), dn(n), ds(n), dth(n), fn(n, 0.0), fs(n, 0.0), mt(n, 0.0) {}
  BondBlock block(std::size_t begin, std::size_t count) {
    return {begin, count, gap.data() + begin, dn.data() + begin, ds.data() + begin, dth.data() + begin,
            fn.data() + begin, fs.data() + begin, mt.data() + begin};
  }
};

}  // namespace

TEST_CASE("contact laws: linear_bond and linear_parallel_bond are plugins with the forces of the pre-plugin code, bit for bit") {
  DemSpec spec;
  spec.tensile_strength_N = 2e-6;  // some bonds break in tension, some in shear
  spec.shear_strength_N = 2.5e-7;
  spec.friction = 0.3;
  spec.damping_ratio_normal = 0.1;
  spec.damping_ratio_shear = 0.05;
  spec.bond_radius_multiplier = 0.8;
  for (const std::string name : {"linear_bond", "linear_parallel_bond"}) {
    CAPTURE(name);
    spec.contact_law = name;
    const auto law = make_contact_law(spec);
    CHECK(law->name() == name);
    std::mt19937_64 rng(7);
    const std::size_t n = 1000;
    BondSet plugin = random_contacts(n, rng), frozen = plugin;
    law->prepare(plugin);
    // prepare as before: c = 2 beta sqrt(m_eff k)
    for (std::size_t i = 0; i < n; ++i) {
      frozen.cn[i] = 2 * spec.damping_ratio_normal * std::sqrt(frozen.m_eff[i] * frozen.kn[i]);
      frozen.cs[i] = 2 * spec.damping_ratio_shear * std::sqrt(frozen.m_eff[i] * frozen.ks[i]);
    }
    std::uniform_real_distribution<double> u(-1, 1);
    Kinematics kp(n), kf(n);
    const double dt = 1e-6;
    std::size_t broke = 0, capped = 0;
    for (int step = 0; step < 5; ++step) {
      for (std::size_t i = 0; i < n; ++i) {
        kp.gap[i] = kf.gap[i] = 0.2e-6 * u(rng);
        kp.dn[i] = kf.dn[i] = 1e-9 * u(rng);
        kp.ds[i] = kf.ds[i] = 5e-8 * u(rng);
        kp.dth[i] = kf.dth[i] = 1e-3 * u(rng);
      }
      const std::vector<std::uint8_t> before = frozen.intact;
      for (std::size_t begin = 0; begin < n; begin += 256) {
        const std::size_t count = std::min<std::size_t>(256, n - begin);
        law->update(plugin, kp.block(begin, count), dt);
        BondBlock fb = kf.block(begin, count);
        frozen_linear_bond_update(frozen, fb, dt, spec.tensile_strength_N, spec.shear_strength_N, spec.friction);
        if (name == "linear_parallel_bond")  // the frozen bending moment (linear_parallel_bond.cpp at 29a51d6)
          for (std::size_t i = 0; i < count; ++i) {
            double& mb = frozen.mb[begin + i];
            mb = frozen.intact[begin + i] ? mb - frozen.kb[begin + i] * fb.dtheta[i] : 0.0;
            fb.m_total[i] = mb;
          }
      }
      for (std::size_t i = 0; i < n; ++i) {
        broke += before[i] && !frozen.intact[i];
        capped += !frozen.intact[i] && frozen.fn[i] > 0 && std::abs(frozen.fs[i]) == spec.friction * frozen.fn[i];
      }
    }
    // Every branch was taken: bonds broke, broken contacts slid at the cap.
    CHECK(broke > 10);
    CHECK(capped > 10);
    CHECK(plugin.cn == frozen.cn);
    CHECK(plugin.cs == frozen.cs);
    CHECK(plugin.fn == frozen.fn);
    CHECK(plugin.fs == frozen.fs);
    CHECK(plugin.intact == frozen.intact);
    CHECK(kp.fn == kf.fn);
    CHECK(kp.fs == kf.fs);
    CHECK(kp.mt == kf.mt);
    CHECK(plugin.mb == frozen.mb);
    // The stable-step stiffness k / (sqrt(1 + beta^2) - beta)^2 and the
    // bending stiffness kn R^2 / 3 (R = 0.8 x 5 um) as before.
    const double f = std::sqrt(1 + 0.1 * 0.1) - 0.1;
    CHECK(law->stable_step_stiffness(26, false) == 26 / (f * f));
    const double R = 0.8 * 5e-6;
    CHECK(law->bending_stiffness(26, 5e-6, 7e-6) == (name == "linear_bond" ? 0.0 : 26 * R * R / 3));
  }
}

TEST_CASE("contact laws: the bundled laws are listed apart from the cell models") {
  const auto laws = available_contact_laws();
  CHECK(std::find(laws.begin(), laws.end(), "linear_bond") != laws.end());
  CHECK(std::find(laws.begin(), laws.end(), "linear_parallel_bond") != laws.end());
  const auto models = PluginRegistry().available();
  CHECK(std::find(models.begin(), models.end(), "colman") != models.end());
  for (const auto& m : models) CHECK(m.find("contact_law") == std::string::npos);
  // Parameters declared like a cell model's, with the seed paper's defaults.
  const auto& info = load_contact_law("linear_parallel_bond")->info();
  REQUIRE(info.parameters.size() == 6);
  CHECK(info.parameters[0].name == "damping_ratio_normal");
  CHECK(info.parameters[0].default_value == 0.1);
  CHECK(info.parameters[5].name == "bond_radius_multiplier");
}

TEST_CASE("contact laws: mechanics.contact_law_parameters sets a law's parameters by name and refuses unknown ones") {
  const json set = {{"contact_law", "linear_bond"},
                    {"friction", 0.2},
                    {"contact_law_parameters", {{"tensile_strength_N", 3e-6}, {"damping_ratio_shear", 0.4}}}};
  JsonReader r(set, "mechanics");
  const DemSpec s = read_dem_spec(r);
  r.finish();
  const auto law = make_contact_law(s);
  // damping_ratio_normal, damping_ratio_shear, tensile_strength_N, shear_strength_N, friction
  CHECK(law->parameters() == std::vector<double>{0.1, 0.4, 3e-6, 1e200, 0.2});

  const json unknown = {{"contact_law", "linear_bond"}, {"contact_law_parameters", {{"bond_radius_multiplier", 2}}}};
  JsonReader ru(unknown, "mechanics");
  try {
    read_dem_spec(ru);
    FAIL("expected a ManifestError");
  } catch (const ManifestError& e) {
    const std::string message = e.what();
    CHECK(message.find("mechanics.contact_law_parameters.bond_radius_multiplier") != std::string::npos);
    CHECK(message.find("linear_bond has no parameter 'bond_radius_multiplier'") != std::string::npos);
    CHECK(message.find("friction") != std::string::npos);  // the names it has
  }
  for (const json& bad : {json{{"contact_law_parameters", 3}}, json{{"contact_law_parameters", {{"friction", "x"}}}},
                          json{{"contact_law", "no_such_law"}}}) {
    JsonReader rb(bad, "mechanics");
    CHECK_THROWS_WITH_AS(read_dem_spec(rb), doctest::Contains("mechanics.contact_law"), ManifestError);
  }
}

TEST_CASE("contact laws: a law built out of tree loads from FIBRODEM_PLUGIN_PATH and follows Hertz's law") {
  setenv("FIBRODEM_PLUGIN_PATH", kTestPlugins.c_str(), 1);
  const json set = {{"contact_law", "hertz_normal"},
                    {"contact_law_parameters", {{"effective_modulus_Pa", 2.0e4}, {"effective_radius_um", 3.0}}}};
  JsonReader r(set, "mechanics");
  const DemSpec s = read_dem_spec(r);
  unsetenv("FIBRODEM_PLUGIN_PATH");
  const auto law = make_contact_law(s);
  REQUIRE(law->name() == "hertz_normal");
  CHECK(law->parameters() == std::vector<double>{2.0e4, 3.0, 2.0});

  // Overlaps d = ref_gap - gap from separated to 2 um pressed.
  const std::vector<double> overlaps_m = {-1e-7, 0.0, 1e-9, 1e-8, 1e-7, 5e-7, 1e-6, 2e-6};
  const std::size_t n = overlaps_m.size();
  BondSet b;
  b.resize(n);
  Kinematics k(n);
  for (std::size_t i = 0; i < n; ++i) {
    b.ref_gap[i] = 0.1e-6;
    k.gap[i] = b.ref_gap[i] - overlaps_m[i];
  }
  law->prepare(b);
  law->update(b, k.block(0, n), 1e-6);
  // Johnson eq. 4.23: F = (4/3) E* sqrt(R*) d^(3/2).
  const double E = 2.0e4, R = 3.0e-6;
  for (std::size_t i = 0; i < n; ++i) {
    CAPTURE(overlaps_m[i]);
    const double d = overlaps_m[i];
    const double expected = d > 0 ? 4.0 / 3.0 * E * std::sqrt(R) * std::pow(d, 1.5) : 0.0;
    CHECK(k.fn[i] == doctest::Approx(expected).epsilon(1e-12));
    CHECK(k.fs[i] == 0.0);
  }
  // Doubling the overlap multiplies the force by 2^(3/2).
  CHECK(k.fn[7] / k.fn[6] == doctest::Approx(std::pow(2.0, 1.5)).epsilon(1e-12));
  // Tangent stiffness 2 E* sqrt(R* d_max) sets the stable step.
  CHECK(law->stable_step_stiffness(26, false) == doctest::Approx(2 * E * std::sqrt(R * 2e-6)).epsilon(1e-12));
}

TEST_CASE("contact laws: summary.json records the law's plugin and every parameter value used") {
  // A myocyte and two fibroblasts, bonded, for 30 ms of DEM.
  json m = json::parse(R"({
    "fibrodem": 1, "name": "law_summary", "seed": 1, "duration_ms": 30,
    "effects": ["electrophysiology", "coupling", "mechanics"],
    "tissue": {"builder": "cell_pair", "fibroblasts": 2},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"law": "gap_junction", "D_f_nS": 0.5},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "mechanics": {"contact_law": "linear_parallel_bond", "friction": 0.3,
                  "contact_law_parameters": {"bond_radius_multiplier": 0.8}}
  })");
  const auto dir = testing::scratch_dir("contact_law_summary");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  const json& law = summary["contact_law"];
  CHECK(law["name"] == "linear_parallel_bond");
  CHECK(law["sha256"].get<std::string>().size() == 64);
  CHECK(law["file"].get<std::string>().find("libfibrodem_contact_law_linear_parallel_bond.so") != std::string::npos);
  CHECK(law["parameters"]["friction"] == 0.3);                // the mechanics key
  CHECK(law["parameters"]["bond_radius_multiplier"] == 0.8);  // contact_law_parameters
  CHECK(law["parameters"]["damping_ratio_normal"] == 0.1);    // the default
  CHECK(law["parameters"].size() == 6);
}

TEST_CASE("contact laws: the bundled laws are described with their parameters, as `fibrodem plugins` lists them") {
  std::vector<std::string> errors;
  const nlohmann::json laws = describe_available_contact_laws(errors);
  CHECK(errors.empty());
  // The two bundled laws and the parameters their plugins declare (plugins/linear_bond, plugins/linear_parallel_bond).
  const std::map<std::string, std::vector<std::string>> expected = {
      {"linear_bond", {"damping_ratio_normal", "damping_ratio_shear", "tensile_strength_N", "shear_strength_N", "friction"}},
      {"linear_parallel_bond", {"bond_radius_multiplier"}}};
  for (const auto& entry : expected) {
    const std::string& name = entry.first;  // (not a structured binding: clang 14 cannot capture one)
    CAPTURE(name);
    const auto law = std::find_if(laws.begin(), laws.end(), [&](const auto& l) { return l["name"] == name; });
    REQUIRE(law != laws.end());
    CHECK((*law)["sha256"].get<std::string>().size() == 64);
    CHECK((*law)["file"].get<std::string>().find("libfibrodem_contact_law_" + name) != std::string::npos);
    for (const auto& parameter : entry.second) {
      CAPTURE(parameter);
      CHECK(std::any_of((*law)["parameters"].begin(), (*law)["parameters"].end(),
                        [&](const auto& p) { return p["name"] == parameter; }));
    }
  }
}
