// Accuracy measurement (core/measure/accuracy.hpp) and the log-log plot writer
// (core/io/plot_png.hpp) behind `fibrodem bench accuracy`.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "io/plot_png.hpp"
#include "measure/accuracy.hpp"
#include "run/run_record.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

BeatBiomarkers beat(int cell, int index, double activation, double apd90) {
  BeatBiomarkers b;
  b.cell = cell;
  b.beat = index;
  b.activation_ms = activation;
  b.apd90_ms = apd90;
  return b;
}

RunRecord synthetic_reference() {
  RunRecord r;
  r.times_ms = {0, 1, 2, 3, 4};
  r.columns = {"V_0", "V_1", "Ca_i_0"};
  r.samples = {{0, 0, 0, 0, 0}, {5, 5, 5, 5, 5}, {1, 1, 1, 1, 1}};
  r.beats = {beat(0, 0, 10, 100), beat(1, 0, 12, 110), beat(1, 1, 1012, std::nan(""))};
  r.cv_cm_per_s = 50.0;
  return r;
}

}  // namespace

TEST_CASE("accuracy: V error on the common sample times of the shared V columns") {
  const RunRecord ref = synthetic_reference();
  RunRecord cand;
  cand.times_ms = {0, 0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5};  // finer, and longer
  cand.columns = {"Ca_i_0", "V_0", "V_10"};                    // V_1 missing, V_10 not in ref
  cand.samples = {{9, 9, 9, 9, 9, 9, 9, 9, 9, 9},
                  {3, 100, 0, 100, -4, 100, 0, 100, 0, 100},
                  {7, 7, 7, 7, 7, 7, 7, 7, 7, 7}};
  cand.beats = ref.beats;
  cand.cv_cm_per_s = 50.0;
  const AccuracyErrors e = compare_runs(ref, cand);
  CHECK(e.v_samples == 5);                                   // V_0 at t = 0..4 only
  CHECK(e.v_max_mV == doctest::Approx(4));
  CHECK(e.v_rms_mV == doctest::Approx(std::sqrt((9.0 + 16.0) / 5.0)));
  CHECK(e.apd90_max_ms == 0);
  CHECK(e.activation_max_ms == 0);
  CHECK(e.beats_compared == 3);
  CHECK(e.beats_mismatched == 0);
  CHECK(e.cv_abs_cm_per_s == 0);
  // Another variable can be compared the same way.
  CHECK(compare_runs(ref, cand, "Ca_i").v_max_mV == doctest::Approx(8));
}

TEST_CASE("accuracy: APD90, activation and CV errors, missing beats are mismatches") {
  const RunRecord ref = synthetic_reference();
  RunRecord cand;
  cand.beats = {beat(1, 1, 1012.75, std::nan("")), beat(0, 0, 10.5, 101), beat(1, 0, 12.25, 108)};
  cand.cv_cm_per_s = 45.0;
  AccuracyErrors e = compare_runs(ref, cand);
  CHECK(e.apd90_max_ms == doctest::Approx(2));
  CHECK(e.activation_max_ms == doctest::Approx(0.75));
  CHECK(e.beats_mismatched == 0);
  CHECK(e.cv_abs_cm_per_s == doctest::Approx(5));
  CHECK(e.cv_rel == doctest::Approx(0.1));
  CHECK(e.v_samples == 0);
  CHECK(std::isnan(e.v_rms_mV));  // nothing traced: no V error, not zero

  // A beat lost, or an action potential that does not repolarise, or no CV.
  cand.beats.pop_back();
  cand.beats[1].apd90_ms = std::nan("");
  cand.cv_cm_per_s.reset();
  e = compare_runs(ref, cand);
  CHECK(e.beats_mismatched == 2);
  CHECK(std::isinf(e.apd90_max_ms));
  CHECK(std::isinf(e.activation_max_ms));
  CHECK(std::isinf(e.cv_rel));
}

TEST_CASE("accuracy: the cheapest run meeting an error level") {
  auto run = [](std::string method, double setting, double wall, double apd, bool completed = true) {
    LadderRun r;
    r.method = std::move(method);
    r.setting = setting;
    r.wall_s = wall;
    r.completed = completed;
    r.errors.apd90_max_ms = apd;
    return r;
  };
  const std::vector<LadderRun> runs = {
      run("euler", 0.001, 0.5, 0.05),      run("euler", 0.01, 0.1, 3.0),
      run("rush_larsen", 0.01, 0.2, 0.5),  run("rush_larsen", 0.05, 0.04, 0.08),  // lucky cancellation
      run("cvode", 1e-3, 0.05, 0.01, false), run("cvode", 1e-4, 0.08, std::nan("")),
      run("cvode", 1e-5, 0.3, 0.08),       run("cvode", 1e-6, 0.4, 0.01)};
  const auto apd = [](const AccuracyErrors& e) { return e.apd90_max_ms; };
  CHECK(cheapest_meeting(runs, apd, 10) == std::optional<std::size_t>(3));
  CHECK(cheapest_meeting(runs, apd, 1) == std::optional<std::size_t>(3));
  // rush_larsen 0.05 ms meets 0.1 ms but its finer step does not: it does not count.
  CHECK(cheapest_meeting(runs, apd, 0.1) == std::optional<std::size_t>(6));
  CHECK(cheapest_meeting(runs, apd, 0.1, "rush_larsen") == std::nullopt);
  CHECK(cheapest_meeting(runs, apd, 0.1, "euler") == std::optional<std::size_t>(0));
  // Failed and NaN runs never count, nor do coarser runs above them.
  CHECK(cheapest_meeting(runs, apd, 0.01, "cvode") == std::optional<std::size_t>(7));
  CHECK_FALSE(cheapest_meeting(runs, apd, 0.001).has_value());
  CHECK_FALSE(cheapest_meeting(runs, apd, 10, "rush_larsen2").has_value());
}

TEST_CASE("accuracy: forward Euler's V error on a passive cell halves when dt halves") {
  json m = testing::passive_cell_manifest();  // 100 ms of a charging RC membrane, samples every 1 ms
  auto record = [&](const json& solver) {
    m["solver"] = solver;
    Simulation sim(parse_scene(m));
    sim.run();
    return record_of(sim);
  };
  const RunRecord reference = record({{"method", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-10}});
  std::vector<double> rms, max;
  for (double dt : {0.1, 0.05, 0.025}) {
    const AccuracyErrors e = compare_runs(reference, record({{"method", "euler"}, {"dt_ms", dt}}));
    REQUIRE(e.v_samples == 101);
    rms.push_back(e.v_rms_mV);
    max.push_back(e.v_max_mV);
  }
  CHECK(rms[0] > 1e-4);  // a measurable first-order error, far above the reference's
  for (std::size_t i = 0; i + 1 < rms.size(); ++i) {
    CAPTURE(i);
    CHECK(rms[i] / rms[i + 1] == doctest::Approx(2).epsilon(0.05));
    CHECK(max[i] / max[i + 1] == doctest::Approx(2).epsilon(0.05));
  }
}

TEST_CASE("plot: a log-log line plot is a PNG of the requested size") {
  const auto dir = testing::scratch_dir("plot_png");
  PlotPanel a;
  a.title = "APD90";
  a.x_label = "wall time (s)";
  a.y_label = "error (ms)";
  a.series = {{"euler", {0.01, 0.1, 1}, {10, 1, 0.1}},
              {"cvode", {0.002, 0.02}, {1e-3, 0.0}}};  // a zero cannot be drawn on a log axis: left out
  a.guides = {{1.0, "1 ms"}};
  PlotPanel b = a;
  b.series.clear();  // an empty panel says so
  PlotOptions options;
  options.width_px = 640;
  options.height_px = 360;
  options.title = "test";
  write_plot_png({a, b}, dir / "plot.png", options);
  const std::string png = testing::read_file(dir / "plot.png");
  REQUIRE(png.size() > 24);
  CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(png[at])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(png[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(png[at + 2])) << 8) |
           static_cast<unsigned>(static_cast<unsigned char>(png[at + 3]));
  };
  CHECK(png.compare(12, 4, "IHDR") == 0);
  CHECK(be32(16) == 640);
  CHECK(be32(20) == 360);
  CHECK_THROWS(write_plot_png({a}, dir / "plot.png" / "x.png", options));  // a file is no directory
}
