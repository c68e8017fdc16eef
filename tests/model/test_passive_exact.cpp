// A passive cell under a constant current against its exact solution, and a
// passive strand against the steady state of its linear system.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
// Passive fibroblast defaults (MacCannell 2007): C 6.3 pF, R 10.7 GOhm, E -49.6 mV.
constexpr double C_pF = 6.3, R_GOhm = 10.7, E_mV = -49.6, I_pA = 1.0;

// V(t) = E + I R (1 - exp(-t / RC)); I R in mV for pA x GOhm.
double exact_V(double t_ms) { return E_mV + I_pA * R_GOhm * (1.0 - std::exp(-t_ms / (R_GOhm * C_pF))); }

double max_error(const json& manifest) {
  Simulation sim(parse_scene(manifest));
  sim.run();
  const auto& t = sim.trace_times();
  const auto& V = sim.trace("V", 0);
  REQUIRE(t.size() == 101);
  double err = 0;
  for (std::size_t i = 0; i < t.size(); ++i) err = std::max(err, std::abs(V[i] - exact_V(t[i])));
  return err;
}
}  // namespace

TEST_CASE("forward Euler on a passive cell converges at first order to the exact solution") {
  json m = testing::passive_cell_manifest();
  m["solver"]["dt_ms"] = 0.2;
  const double e1 = max_error(m);
  m["solver"]["dt_ms"] = 0.1;
  const double e2 = max_error(m);
  m["solver"]["dt_ms"] = 0.05;
  const double e3 = max_error(m);
  // Global error of Euler is O(dt): halving dt halves it (ratio 2 within 5 %).
  CHECK(e1 / e2 == doctest::Approx(2.0).epsilon(0.05));
  CHECK(e2 / e3 == doctest::Approx(2.0).epsilon(0.05));
  // Leading-order theory: the global error of Euler on y' = -(y - y_inf)/tau is
  // e(t) = (dt/2) (t/tau^2) I R exp(-t/tau), largest at t = tau: dt I R / (2 e tau).
  const double tau = R_GOhm * C_pF;
  CHECK(e3 == doctest::Approx(0.05 * I_pA * R_GOhm / (2.0 * std::exp(1.0) * tau)).epsilon(0.02));
}

TEST_CASE("Rush-Larsen equals Euler for a state that is not a gate") {
  json m = testing::passive_cell_manifest();
  m["solver"]["dt_ms"] = 0.1;
  const double euler = max_error(m);
  m["solver"]["method"] = "rush_larsen";
  CHECK(max_error(m) == euler);
}

TEST_CASE("CVODE on a passive cell stays within its tolerance of the exact solution") {
  json m = testing::passive_cell_manifest();
  m["solver"] = {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-8}};
  // Local error control at rtol 1e-8 on |V| ~ 50 mV: each step's error is below
  // ~5e-7 mV; the global error of this contracting problem stays of that order.
  CHECK(max_error(m) < 1e-5);
  m["solver"]["rtol"] = 1e-4;
  m["solver"]["atol"] = 1e-4;
  const double loose = max_error(m);
  CHECK(loose < 5e-2);
  CHECK(loose > 1e-5);  // a looser tolerance really costs accuracy: the check can fail
}

TEST_CASE("a passive strand under constant current reaches the steady state of its linear system") {
  // 5 fibroblasts in a chain, D_f = 0.5 nS, 2 pA into cell 0. Steady state:
  // (G_leak I + L) (V - E) = i  with G_leak = 1/R per cell, L the chain Laplacian.
  constexpr int n = 5;
  constexpr double D_nS = 0.5, i0_pA = 2.0;
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", n}};
  m["coupling"] = {{"D_f_nS", D_nS}};
  m["stimulus"] = json::array({{{"target", {0}}, {"start_ms", 0}, {"duration_ms", 1e6}, {"amplitude_pA", i0_pA}}});
  m["duration_ms"] = 2000;  // ~30 membrane time constants
  m["solver"] = {{"method", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-10}};
  m["output"]["traces"] = {{"cells", {0, 1, 2, 3, 4}}, {"variables", {"V"}}, {"every_ms", 100}};
  Simulation sim(parse_scene(m));
  sim.run();

  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) / R_GOhm;
  for (int k = 0; k + 1 < n; ++k) {
    A(k, k) += D_nS;
    A(k + 1, k + 1) += D_nS;
    A(k, k + 1) -= D_nS;
    A(k + 1, k) -= D_nS;
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  rhs(0) = i0_pA;
  const Eigen::VectorXd dV = A.fullPivLu().solve(rhs);
  for (int k = 0; k < n; ++k) {
    CAPTURE(k);
    // exp(-2000/67.4) ~ 1e-13: the transient is gone; tolerance = CVODE's.
    CHECK(sim.trace("V", k).back() == doctest::Approx(E_mV + dV(k)).epsilon(1e-8));
  }
  // The current spreads: the far end is depolarised less than the injected end.
  CHECK(dV(n - 1) < dV(0));
}

TEST_CASE("second-order Rush-Larsen converges at second order on a passive cell") {
  json m = testing::passive_cell_manifest();
  m["solver"]["method"] = "rush_larsen2";
  m["solver"]["dt_ms"] = 0.5;
  const double e1 = max_error(m);
  m["solver"]["dt_ms"] = 0.25;
  const double e2 = max_error(m);
  // Halving dt divides the error by 4 (within 5 %).
  CHECK(e1 / e2 == doctest::Approx(4.0).epsilon(0.05));
  // And at the same step it beats first-order Euler by far.
  m["solver"]["method"] = "euler";
  CHECK(max_error(m) > 50 * e2);
}
