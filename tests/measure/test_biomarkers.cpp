// Biomarkers measured on a synthetic action potential whose values are known
// in closed form.
#include <doctest/doctest.h>

#include <cmath>

#include "measure/biomarkers.hpp"

using namespace fibrodem;

namespace {
constexpr double kPi = 3.14159265358979323846;
// Rest at -80 mV; at t = 10 ms a half-cosine upstroke to +20 mV over 1 ms
// (steepest at 10.5 ms, dV/dt = 50 pi mV/ms); then a linear repolarisation
// back to -80 mV over 300 ms; rest again.
double synthetic_V(double t) {
  if (t <= 10) return -80;
  if (t <= 11) return -80 + 50 * (1 - std::cos(kPi * (t - 10)));
  if (t <= 311) return 20 - 100 * (t - 11) / 300;
  return -80;
}

std::vector<BeatBiomarkers> measure(double h, std::vector<double> onsets, double until) {
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker({CellType::myocyte}, onsets, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  double V = synthetic_V(0);
  tracker.start(0, &V);
  const long n = std::lround(until / h);
  for (long k = 0; k < n; ++k) {
    const double t_new = (k + 1) * h;
    V = synthetic_V(t_new);
    tracker.step(k * h, t_new, &V, nullptr);
  }
  tracker.finish();
  return beats;
}
}  // namespace

TEST_CASE("APD90, APD50, APO, RMP and max dV/dt of a synthetic action potential") {
  const auto beats = measure(0.01, {10.0}, 500.0);
  REQUIRE(beats.size() == 1);
  const auto& b = beats[0];
  CHECK(b.rmp_mV == doctest::Approx(-80));
  CHECK(b.apo_mV == doctest::Approx(20));
  // The difference quotient over a step h = 0.01 ms centred up to h/2 off the
  // steepest point: relative error <= (pi h/2)^2/2 + (pi h)^2/24 = 1.6e-4.
  CHECK(b.dvdt_max_mV_per_ms == doctest::Approx(50 * kPi).epsilon(2e-4));
  CHECK(b.dvdt_max_mV_per_ms <= 50 * kPi);
  // Activation at the steepest point, 10.5 ms, to within a step.
  CHECK(b.activation_ms == doctest::Approx(10.5).epsilon(0.01 / 10.5));
  // APD90 ends at V = RMP + 0.1 APA = -70 mV: t = 11 + 0.9 * 300 = 281 ms.
  CHECK(b.apd90_ms == doctest::Approx(281 - b.activation_ms).epsilon(1e-9));
  CHECK(b.apd90_ms == doctest::Approx(270.5).epsilon(0.01 / 270.5));
  // APD50 ends at V = -30 mV: t = 11 + 0.5 * 300 = 161 ms.
  CHECK(b.apd50_ms == doctest::Approx(161 - b.activation_ms).epsilon(1e-9));
}

TEST_CASE("beats are cut at stimulus onsets, a beat that does not repolarise has no APD") {
  // Second onset at 200 ms: the first beat ends before the -70 mV crossing.
  const auto beats = measure(0.01, {10.0, 200.0}, 400.0);
  REQUIRE(beats.size() == 2);
  CHECK(std::isnan(beats[0].apd90_ms));
  CHECK(beats[0].apd50_ms == doctest::Approx(161 - beats[0].activation_ms).epsilon(1e-9));
  CHECK(beats[1].beat == 1);
  // RMP of beat 1 is V at its onset (mid-repolarisation): 20 - 100 * 189 / 300.
  CHECK(beats[1].rmp_mV == doctest::Approx(20 - 100 * 189.0 / 300).epsilon(1e-9));
}

TEST_CASE("an integrator's own dV/dt is used when it gives one") {
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker({CellType::fibroblast}, {}, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  double V = -50;
  tracker.start(0, &V);
  double slope = 3.0;
  V = -49;
  tracker.step(0, 1, &V, &slope);  // difference quotient would say 1 mV/ms
  tracker.finish();
  REQUIRE(beats.size() == 1);
  CHECK(beats[0].dvdt_max_mV_per_ms == 3.0);
  CHECK(beats[0].activation_ms == 1.0);
  CHECK(beats[0].type == CellType::fibroblast);
}

TEST_CASE("with the integrator's dV/dt, APD crossings inside long steps follow the curve, not the chord") {
  // Upstroke at t = 0 to +20 mV, then V = -80 + 100 exp(-t / 100) (never quite
  // back to rest): RMP -80, APA 100, so APD90 ends at -70 mV, t = 100 ln 10,
  // and APD50 at -30 mV, t = 100 ln 2. Steps of 5 ms as CVODE takes in late
  // repolarisation: the chord would miss by 0.006 ms (APD90) and 0.015 ms (APD50).
  auto V_at = [](double t) { return -80 + 100 * std::exp(-t / 100); };
  auto dVdt_at = [](double t) { return -std::exp(-t / 100); };
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker({CellType::myocyte}, {-1.0}, -10.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  double V = -80, slope = 0;
  tracker.start(-2, &V);
  tracker.step(-2, -1, &V, &slope);  // the beat opens at -1, at rest
  V = 20, slope = 1000;              // the upstroke: the steepest point is t = 0
  tracker.step(-1, 0, &V, &slope);
  for (double t = 0; t < 400; t += 5) {
    V = V_at(t + 5), slope = dVdt_at(t + 5);
    tracker.step(t, t + 5, &V, &slope);
  }
  tracker.finish();
  REQUIRE(beats.size() == 1);
  // Cubic Hermite over h = 5 ms: error ~ h^4 V'''' / 384 ~ 2e-9 mV, so ~2e-6 ms in time.
  const double t_act = beats[0].activation_ms;
  CHECK(beats[0].apd90_ms + t_act == doctest::Approx(100 * std::log(10.0)).epsilon(1e-7));
  CHECK(beats[0].apd50_ms + t_act == doctest::Approx(100 * std::log(2.0)).epsilon(1e-7));
}

TEST_CASE("with the integrator's dV/dt, the activation time and max dV/dt come from the peak between samples") {
  // The half-cosine upstroke of synthetic_V, its exact dV/dt given at step ends
  // 0.1 ms apart that miss the steepest point (10.5 ms) by 0.03 ms: the samples
  // alone would place activation at 10.53 ms.
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker({CellType::myocyte}, {9.0}, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  auto slope_at = [](double t) { return t > 10 && t < 11 ? 50 * kPi * std::sin(kPi * (t - 10)) : 0.0; };
  double V = synthetic_V(8.93), slope = 0;
  tracker.start(8.93, &V);
  for (double t = 8.93; t < 12; t += 0.1) {
    V = synthetic_V(t + 0.1), slope = slope_at(t + 0.1);
    tracker.step(t, t + 0.1, &V, &slope);
  }
  tracker.finish();
  REQUIRE(beats.size() == 1);
  // Parabola through samples 0.1 ms apart on a sine of period 2 ms: the vertex
  // is off by 1.6e-4 ms. Max dV/dt stays the largest sample (at 10.53 ms).
  CHECK(beats[0].activation_ms == doctest::Approx(10.5).epsilon(2e-4 / 10.5));
  CHECK(beats[0].dvdt_max_mV_per_ms == doctest::Approx(50 * kPi * std::sin(kPi * 0.53)).epsilon(1e-12));
}

TEST_CASE("from difference quotients, the activation time is refined between samples, cell by cell") {
  // synthetic_V's half-cosine upstroke, in steps of 0.1 ms, each cell's
  // steps shifted: over [t, t + h] the difference quotient is
  // 100 sin(pi h / 2) / h x sin(pi (m - 10)), m = t + h / 2, a sine sampled
  // at the steps' middles (cell 0: 10.48 and 10.58 ms about the steepest
  // point, 10.5). The parabola through the largest sample and its
  // neighbours, both on adjacent steps (every step of an upstroke is
  // measured), finds 10.5 to ~1e-4 ms (as with the integrator's dV/dt,
  // above); the largest sample alone would be up to 0.05 ms off. Max dV/dt
  // is the largest sample.
  const double h = 0.1;
  const std::vector<double> shift_ms = {0.0, 0.03, 0.07};
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker(std::vector<CellType>(shift_ms.size(), CellType::myocyte), {9.0}, 0.0,
                           [&](const BeatBiomarkers& b) { beats.push_back(b); });
  const auto V_at = [&](double t, std::vector<double>& V) {
    for (std::size_t c = 0; c < shift_ms.size(); ++c) V[c] = synthetic_V(t - shift_ms[c]);
  };
  std::vector<double> V(shift_ms.size());
  V_at(8.93, V);
  tracker.start(8.93, V.data());
  for (long k = 0; k < 40; ++k) {
    const double t = 8.93 + k * h;
    V_at(t + h, V);
    tracker.step(t, t + h, V.data(), nullptr);
  }
  tracker.finish();
  REQUIRE(beats.size() == shift_ms.size());
  const double K = 100 * std::sin(kPi * h / 2) / h;
  for (std::size_t c = 0; c < shift_ms.size(); ++c) {
    CAPTURE(c);
    const double steepest_ms = 10.5 + shift_ms[c];
    CHECK(beats[c].activation_ms == doctest::Approx(steepest_ms).epsilon(2e-4 / steepest_ms));
    // The sample nearest 10.5 ms after the shift: middles at 8.98 + 0.1 k.
    const double m = 8.98 + std::round((steepest_ms - 8.98) / h) * h;
    CHECK(beats[c].dvdt_max_mV_per_ms == doctest::Approx(K * std::sin(kPi * (m - shift_ms[c] - 10))).epsilon(1e-9));
  }
}

TEST_CASE("the pre-upstroke RMP is the mean V over the window before activation, on the bucket grid") {
  // Rest at -80 mV to t = 50 ms, a linear foot to -70 mV at 60 ms, then a
  // steep upstroke (activation at its steepest point, 60.5 ms) to +20 mV.
  auto V_of = [](double t) {
    if (t <= 50) return -80.0;
    if (t <= 60) return -80.0 + (t - 50);
    if (t <= 61) return -70.0 + 45 * (1 - std::cos(kPi * (t - 60)));
    return 20.0;
  };
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker({CellType::myocyte}, {40.0}, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  tracker.use_pre_upstroke_rmp(5.0, 2.0);
  double V = V_of(0);
  tracker.start(0, &V);
  const double h = 0.01;
  for (long k = 0; k < 8000; ++k) {
    V = V_of((k + 1) * h);
    tracker.step(k * h, (k + 1) * h, &V, nullptr);
  }
  tracker.finish();
  REQUIRE(beats.size() == 1);
  CHECK(beats[0].activation_ms == doctest::Approx(60.5).epsilon(1e-3));
  // Buckets of 5/8 ms: the window ends at the boundary at or before
  // 60.5 - 2 = 58.5 ms, i.e. 58.125 (93 x 0.625), and starts 5 ms earlier at
  // 53.125; V is linear there, so its mean is V at the middle, 55.625 ms.
  CHECK(beats[0].rmp_mV == doctest::Approx(-80.0 + (55.625 - 50)).epsilon(1e-9));
  // The APD level still uses V at the onset (-80 mV), so APO is unchanged.
  CHECK(beats[0].apo_mV == doctest::Approx(20.0));
  // Without the option: V at the onset (40 ms).
  beats.clear();
  BiomarkerTracker plain({CellType::myocyte}, {40.0}, 0.0, [&](const BeatBiomarkers& b) { beats.push_back(b); });
  V = V_of(0);
  plain.start(0, &V);
  for (long k = 0; k < 8000; ++k) {
    V = V_of((k + 1) * h);
    plain.step(k * h, (k + 1) * h, &V, nullptr);
  }
  plain.finish();
  CHECK(beats.at(0).rmp_mV == -80.0);
}
