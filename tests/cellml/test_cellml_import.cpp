// `fibrodem import-cellml`: plugins generated from small CellML models written
// for these tests (tests/cellml, in CellML 1.0, 1.1 and 2.0) against analytic
// solutions and independent integrations of the published equations; models
// it must refuse, with the element's path.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "cellml/import.hpp"
#include "cellml/import_error.hpp"
#include "model/plugin_registry.hpp"
#include "support/cellml_plugins.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

namespace {

using testing::index_of;
using testing::kCellml;
using testing::kGenerated;
using testing::load;
using testing::rk4;
using testing::without_origin;

// One cell, classic RK4 on dy/dt = a + b y as the model returns it.
struct OneCell {
  std::shared_ptr<const CellModel> model;
  std::vector<double> y, outputs;  // outputs: as the last evaluation left them
  OneCell(std::shared_ptr<const CellModel> m) : model(std::move(m)) {
    for (const auto& s : model->info().states) y.push_back(s.initial);
    outputs.assign(model->info().outputs.size(), 0.0);
  }
  bool lanes = false;  // evaluate in SIMD lanes instead of the scalar reference path
  std::vector<double> rates(const std::vector<double>& state, double t, double i_ext) {
    testing::Rates r = testing::evaluate(*model, state, t, i_ext, lanes);
    outputs = std::move(r.outputs);
    return r.dydt;
  }
  void step(double t, double dt, const std::function<double(double)>& i_ext) {
    auto add = [](std::vector<double> x, const std::vector<double>& k, double h) {
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += h * k[i];
      return x;
    };
    const auto k1 = rates(y, t, i_ext(t));
    const auto k2 = rates(add(y, k1, dt / 2), t + dt / 2, i_ext(t + dt / 2));
    const auto k3 = rates(add(y, k2, dt / 2), t + dt / 2, i_ext(t + dt / 2));
    const auto k4 = rates(add(y, k3, dt), t + dt, i_ext(t + dt));
    for (std::size_t i = 0; i < y.size(); ++i) y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
};


fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("fibrodem_cellml_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir;
}

std::string import_error_of(const std::string& file, const fs::path& out) {
  cellml::ImportOptions o;
  o.input = kCellml / "errors" / file;
  o.name = "refused";
  o.out = out;
  try {
    cellml::import_cellml(o);
  } catch (const cellml::ImportError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("import-cellml: a passive RC membrane follows its analytic charging curve") {
  // C dV/dt = I - (V - E)/R from V = E: V(t) = E + I R (1 - exp(-t / (R C))).
  // C 6.3 pF, R 10.7 GOhm, E -49.6 mV (the CellML's values); I 10 pA: I R = 107 mV, RC = 67.41 ms.
  auto model = load("cellml_rc");
  const auto& info = model->info();
  REQUIRE(info.states.size() == 1);
  CHECK(info.states[0].name == "V");
  CHECK(info.parameters[info.capacitance_parameter].default_value == doctest::Approx(6.3));
  OneCell cell(model);
  const double I = 10.0, E = -49.6, R = 10.7, C = 6.3;
  double t = 0.0;
  const double dt = 0.01;
  for (double check : {10.0, 50.0, 150.0}) {
    while (t < check - 1e-9) {
      cell.step(t, dt, [&](double) { return I; });
      t += dt;
    }
    const double exact = E + I * R * (1.0 - std::exp(-t / (R * C)));
    CHECK(cell.y[0] == doctest::Approx(exact).epsilon(1e-9));  // RK4 at dt/tau 1.5e-4: error ~1e-14
    cell.rates(cell.y, t, I);
    CHECK(cell.outputs[0] == doctest::Approx((cell.y[0] - E) / R).epsilon(1e-9));  // I_ion, pA
  }
}

TEST_CASE("import-cellml: Hodgkin-Huxley 1952 matches the paper's equations integrated independently") {
  auto model = load("cellml_hh");
  const auto& info = model->info();
  const int kV = index_of(info.states, "V"), km = index_of(info.states, "m"), kh = index_of(info.states, "h"),
            kn = index_of(info.states, "n");
  for (int k : {km, kh, kn}) {
    CHECK(info.states[k].gate);
    CHECK(info.states[k].voltage_only);
    CHECK(info.states[k].lower == 0.0);
    CHECK(info.states[k].upper == 1.0);
  }
  // uA/cm^2 model: C_pF = 1 uF/cm^2 x 1e-4 cm^2 = 100 pF.
  CHECK(info.parameters[info.capacitance_parameter].default_value == doctest::Approx(100.0));
  // The paper's equations (J Physiol 117:500, eqs. 5-26, V shifted to rest at -75 mV),
  // written here independently; stimulus 20 uA/cm^2 = 2000 pA over 100 pF for 0.5 ms.
  auto stim = [](double t) { return t >= 10.0 && t < 10.5 ? 20.0 : 0.0; };
  auto hh = [&](double t, const std::array<double, 4>& s) {
    const double V = s[0], m = s[1], h = s[2], n = s[3];
    const double am = 0.1 * (V + 50) / (1 - std::exp(-(V + 50) / 10)), bm = 4 * std::exp(-(V + 75) / 18);
    const double ah = 0.07 * std::exp(-(V + 75) / 20), bh = 1 / (std::exp(-(V + 45) / 10) + 1);
    const double an = 0.01 * (V + 65) / (1 - std::exp(-(V + 65) / 10)), bn = 0.125 * std::exp((V + 75) / 80);
    const double I = 120 * m * m * m * h * (V - 40) + 36 * n * n * n * n * (V + 87) + 0.3 * (V + 64.387);
    return std::array<double, 4>{stim(t) - I, am * (1 - m) - bm * m, ah * (1 - h) - bh * h, an * (1 - n) - bn * n};
  };
  std::array<double, 4> ref{-75, 0.05, 0.6, 0.325};
  OneCell cell(model);
  const double dt = 0.001;
  double peak = -100, max_diff = 0;
  for (int i = 0; i < 30000; ++i) {
    const double t = i * dt;
    rk4(ref, t, dt, hh);
    cell.step(t, dt, [&](double tt) { return stim(tt) * 100.0; });
    max_diff = std::max(max_diff, std::fabs(cell.y[kV] - ref[0]));
    peak = std::max(peak, cell.y[kV]);
  }
  CHECK(max_diff < 1e-6);  // the same equations and method: round-off apart
  // HH 1952 Fig. 12: an action potential ~100-110 mV above rest.
  CHECK(peak > 20.0);
  CHECK(peak < 50.0);
}

TEST_CASE("import-cellml: the removable singularities of HH's alpha_m and alpha_n are their limits") {
  // alpha_m = 0.1 (V + 50)/(1 - exp(-(V + 50)/10)) -> 1 /ms at V = -50;
  // alpha_n = 0.01 (V + 65)/(1 - exp(-(V + 65)/10)) -> 0.1 /ms at V = -65 (l'Hopital).
  OneCell cell(load("cellml_hh"));
  const auto& info = cell.model->info();
  const int kV = index_of(info.states, "V"), km = index_of(info.states, "m"), kn = index_of(info.states, "n");
  for (bool lanes : {false, true}) {
    cell.lanes = lanes;
    auto y = cell.y;
    y[km] = 0.0;
    y[kn] = 0.0;
    y[kV] = -50.0;
    CHECK(cell.rates(y, 0.0, 0.0)[km] == doctest::Approx(1.0).epsilon(1e-12));
    y[kV] = -65.0;
    CHECK(cell.rates(y, 0.0, 0.0)[kn] == doctest::Approx(0.1).epsilon(1e-12));
    y[kV] = -50.0 + 1e-9;  // beside it: the plain formula, to its own precision
    const double x = -(y[kV] + 50) / 10;
    CHECK(cell.rates(y, 0.0, 0.0)[km] == doctest::Approx(0.1 * (y[kV] + 50) / -std::expm1(x)).epsilon(1e-6));
  }
}

TEST_CASE("import-cellml: every translated MathML operator gives what the C++ library computes") {
  // tests/cellml/mathml_coverage_2_0.cellml: dV/dt [mV/ms] = the sum of its groups of functions of
  // x = V / 100 mV, plus a constant chosen by a piecewise on a parameter (pi).
  OneCell cell(load("cellml_mathml"));
  for (bool lanes : {false, true})
    for (double V : {-30.0, 20.0}) {
      cell.lanes = lanes;
      const double x = V / 100.0;
      const double trig = std::sin(x) + std::cos(x) + std::tan(x) + 1 / std::cos(x) + 1 / std::sin(x) + 1 / std::tan(x);
      const double hyp = std::sinh(x) + std::cosh(x) + std::tanh(x) + 1 / std::cosh(x) + 1 / std::sinh(x) + 1 / std::tanh(x);
      const double arc = std::asin(x) + std::acos(x) + std::atan(x) + std::asinh(x) + std::atanh(x) + std::acosh(2 - x) +
                         std::acos(1 / (2 - x)) + std::asin(1 / (2 - x)) + std::atan(1 / x) + std::acosh(2 - x) +
                         std::asinh(1 / x) + std::atanh(1 / (2 - x));
      const double misc = std::fabs(x) + std::floor(10 * x) + std::ceil(10 * x) + std::fmin(x, -0.2) + std::fmax(x, 0.1) +
                          std::fmod(10 * x, 0.7);
      const double pw = std::pow(2 - x, 1.5) + x * x + std::sqrt(4 - x) + std::cbrt(8 - x) + std::exp(x) + std::log(2 - x) +
                        std::log10(10 - x) + std::log2(3 - x);
      const double piecewise = x < 0 ? 1.0 : 2.0;
      const double expected = trig + hyp + arc + misc + pw + piecewise + M_PI;
      auto y = cell.y;
      y[0] = V;
      CHECK_MESSAGE(cell.rates(y, 0.0, 0.0)[0] == doctest::Approx(expected).epsilon(1e-12), "V " << V << " lanes " << lanes);
    }
}

TEST_CASE("import-cellml: FitzHugh-Nagumo rests at FitzHugh's point and oscillates as integrated independently") {
  auto model = load("cellml_fhn");
  const auto& info = model->info();
  OneCell cell(model);
  // FitzHugh 1961: with z = 0 the rest point is x = 1.1994, y = -0.6243.
  const auto r = cell.rates(cell.y, 0.0, 0.0);
  CHECK(std::fabs(r[0]) < 1e-9);
  CHECK(std::fabs(r[1]) < 1e-9);
  CHECK(cell.y[index_of(info.states, "V")] == doctest::Approx(1.1994).epsilon(1e-4));
  // z = -0.4 (oscillatory, FitzHugh's Fig. 2) as i_ext: c V_s z / T = i_ext / C_pF.
  const double C_pF = info.parameters[info.capacitance_parameter].default_value;
  const double i_ext = 3.0 * 1.0 * -0.4 / 1.0 * C_pF;
  auto fhn = [](double, const std::array<double, 2>& s) {
    const double x = s[0], y = s[1], z = -0.4;
    return std::array<double, 2>{3 * (y + x - x * x * x / 3 + z), -(x - 0.7 + 0.8 * y) / 3};
  };
  std::array<double, 2> ref{cell.y[0], cell.y[1]};
  double max_diff = 0, lowest = 10;
  const double dt = 0.001;
  for (int i = 0; i < 50000; ++i) {
    rk4(ref, i * dt, dt, fhn);
    cell.step(i * dt, dt, [&](double) { return i_ext; });
    max_diff = std::max(max_diff, std::fabs(cell.y[0] - ref[0]));
    lowest = std::min(lowest, cell.y[0]);
  }
  CHECK(max_diff < 1e-7);
  CHECK(lowest < -1.5);  // it fired: x swings to ~ -2 on the limit cycle
}

TEST_CASE("import-cellml: CellML 1.0, 1.1 and 2.0 of the same model give the same plugin") {
  for (const std::string model : {"hh_1952", "rc_membrane", "fitzhugh_nagumo", "lumped_stimulus"}) {
    std::string first;
    for (const std::string version : {"1_0", "1_1", "2_0"}) {
      cellml::ImportOptions o;
      o.input = kCellml / (model + "_" + version + ".cellml");
      o.name = model;
      o.out = scratch(model + version);
      if (model == "fitzhugh_nagumo") o.stimulus = "stimulus.z";
      const auto result = cellml::import_cellml(o);
      CHECK(fs::exists(result.folder / "CMakeLists.txt"));
      const std::string text = without_origin(testing::read_file(result.folder / (model + ".cpp")));
      if (first.empty()) first = text;
      else CHECK_MESSAGE(text == first, model << " " << version);
    }
  }
}

TEST_CASE("import-cellml: a state's derivative on a right side is that state's rate") {
  // derivative_on_rhs_1_0.cellml: dO/dt = k_on L (1 - O) - k_off O in 1/s (k_on 200 /mM/s, L 0.5 mM,
  // k_off 476 /s, O0 0.0275); Ca_a and Ca_b (mM, ms) lose B dO/dt (B 0.08 mM), Ca_a through an
  // algebraic d(O)/d(time) connected from per second to per ms, Ca_b through d(O)/d(time) inline.
  // By hand: dO/dt(0) = 100 x 0.9725 - 476 x 0.0275 = 84.16 /s = 0.08416 /ms, dCa/dt(0) = -0.0067328 mM/ms;
  // O(t) = O_inf + (O0 - O_inf) exp(-t / tau), O_inf = 100/576, tau = 1/576 s; Ca(t) = 0.05 - B (O(t) - O0).
  auto model = load("cellml_derivative");
  const auto& info = model->info();
  const int kO = index_of(info.states, "O"), ka = index_of(info.states, "Ca_a"), kb = index_of(info.states, "Ca_b");
  OneCell cell(model);
  const auto r0 = cell.rates(cell.y, 0.0, 0.0);
  CHECK(r0[kO] == doctest::Approx(0.08416).epsilon(1e-12));
  CHECK(r0[ka] == doctest::Approx(-0.0067328).epsilon(1e-12));
  CHECK(r0[kb] == doctest::Approx(-0.0067328).epsilon(1e-12));
  const double O0 = 0.0275, O_inf = 100.0 / 576.0, tau_ms = 1000.0 / 576.0, B = 0.08;
  double t = 0.0;
  const double dt = 0.01;
  for (double check : {1.0, 5.0, 20.0}) {
    while (t < check - 1e-9) {
      cell.step(t, dt, [](double) { return 0.0; });
      t += dt;
    }
    const double O = O_inf + (O0 - O_inf) * std::exp(-t / tau_ms);
    CHECK(cell.y[kO] == doctest::Approx(O).epsilon(1e-10));  // RK4 at dt/tau 0.006: error ~1e-13
    CHECK(cell.y[ka] == doctest::Approx(0.05 - B * (O - O0)).epsilon(1e-10));
    CHECK(cell.y[kb] == doctest::Approx(0.05 - B * (O - O0)).epsilon(1e-10));
  }
}

TEST_CASE("import-cellml: a CellML variable named dV_dt does not clash with the plugin's own") {
  // dv_dt_named_2_0.cellml: dV/dt = dV_dt = (i_stim - g (V - E)) / C, C 10 pF, g 2 nS, E -80 mV, V0 -70 mV.
  // By hand at V0: g (V - E) = 20 pA; dV/dt = -2 mV/ms with i_ext 0, (50 - 20) / 10 = 3 mV/ms with i_ext
  // 50 pA; I_ion = i_ext - C dV/dt = 20 pA either way.
  auto model = load("cellml_dv_dt_named");
  REQUIRE(model->info().states.size() == 1);
  OneCell cell(model);
  CHECK(cell.rates(cell.y, 0.0, 0.0)[0] == doctest::Approx(-2.0).epsilon(1e-12));
  CHECK(cell.outputs[0] == doctest::Approx(20.0).epsilon(1e-12));
  CHECK(cell.rates(cell.y, 0.0, 50.0)[0] == doctest::Approx(3.0).epsilon(1e-12));
  CHECK(cell.outputs[0] == doctest::Approx(20.0).epsilon(1e-12));
}

TEST_CASE("import-cellml: refusals name the element and leave no plugin behind") {
  const fs::path out = scratch("refused");
  const std::string loop = import_error_of("algebraic_loop.cellml", out);
  CHECK(loop.find("algebraic loop") != std::string::npos);
  CHECK(loop.find("/model[@name='algebraic_loop']/component[@name='membrane']/math/apply[") != std::string::npos);
  CHECK(loop.find("(line ") != std::string::npos);
  const std::string element = import_error_of("unsupported_element.cellml", out);
  CHECK(element.find("unsupported MathML element <factorial>") != std::string::npos);
  CHECK(element.find("/component[@name='membrane']/math/apply/apply[2]/apply/factorial (line 11)") != std::string::npos);
  const std::string units = import_error_of("inconsistent_units.cellml", out);
  CHECK(units.find("inconsistent units") != std::string::npos);
  CHECK(units.find("/model[@name='inconsistent_units']/connection/map_variables (line 18)") != std::string::npos);
  const std::string algebraic = import_error_of("derivative_of_algebraic.cellml", out);
  CHECK(algebraic.find("d(a)/d(time) on a right side: membrane.a is not a state") != std::string::npos);
  CHECK(algebraic.find("/component[@name='membrane']/math/apply[2]/apply[2]/apply (line 13)") != std::string::npos);
  const std::string itself = import_error_of("derivative_of_itself.cellml", out);
  CHECK(itself.find("the rate of membrane.x is defined through its own derivative") != std::string::npos);
  // Slips inside equations are warnings (test_cellml_units.cpp).
  CHECK_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(out.parent_path()))
    CHECK(entry.path().filename().string().find(".importing-") == std::string::npos);
}
