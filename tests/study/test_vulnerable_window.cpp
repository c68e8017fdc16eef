// `fibrodem vulnerable-window`: the scan and bisection of the S1-S2 coupling
// interval (study/vulnerable_window.hpp).
#include <doctest/doctest.h>

#include <cmath>
#include <map>

#include "model/plugin_registry.hpp"
#include "study/vulnerable_window.hpp"
#include "support/scenes.hpp"
#include "util/manifest_error.hpp"

using namespace fibrodem;

namespace {

// A classifier with known windows per seed: induced iff the interval lies
// in one of [lo, hi] (inclusive), counting the probes it was asked for.
struct SyntheticTissue {
  std::map<long long, std::vector<std::pair<double, double>>> windows;
  std::size_t probes = 0;
  S2Classifier classifier() {
    return [this](const std::vector<S2Probe>& batch) {
      std::vector<S2Result> out;
      for (const auto& p : batch) {
        ++probes;
        S2Result r;
        r.probe = p;
        r.outcome = S2Outcome::no_reentry;
        for (auto [lo, hi] : windows.at(p.seed))
          if (p.interval_ms >= lo && p.interval_ms <= hi) r.outcome = S2Outcome::reentry;
        out.push_back(r);
      }
      return out;
    };
  }
};

// A cAF strand (a one-column-wide sheet, D_m_nS 5) paced by S1 at 10 ms and
// S2 at 200 ms at its lower end, 400 ms.
json s1s2_strand() {
  return json::parse(R"({"fibrodem": 1, "name": "strand", "duration_ms": 400, "seed": 1,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.05, "length_mm": 3},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013_caf"}},
    "coupling": {"D_m_nS": 5},
    "stimulus": [
      {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2}, "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000},
      {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2}, "start_ms": 200, "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "auto"},
    "output": {"report": false}})");
}

// A search whose runs are made in this process, two at a time, under dir.
VulnerableWindowOptions in_process_search(const std::filesystem::path& dir) {
  VulnerableWindowOptions options;
  options.out = dir / "search";
  options.runner = InProcessRunner{PluginRegistry::search_path_beside(FIBRODEM_BINARY_DIR)};
  options.jobs = 2;
  return options;
}

}  // namespace

TEST_CASE("the bisection finds a synthetic window's ends to the resolution") {
  // Window [143.5, 187.2] ms: on the 1 ms grid from 100 the induced intervals
  // are 144..187, so the search must report exactly [144, 187].
  SyntheticTissue tissue{{{7, {{143.5, 187.2}}}}};
  const WindowScan scan{100, 300, 20, 1};
  const WindowSearch s = search_vulnerable_window(scan, {7}, tissue.classifier());
  REQUIRE(s.per_seed.size() == 1);
  REQUIRE(s.per_seed[0].windows.size() == 1);
  CHECK(s.per_seed[0].windows[0].lower_ms == 144);
  CHECK(s.per_seed[0].windows[0].upper_ms == 187);
  CHECK_FALSE(s.per_seed[0].windows[0].open_below);
  CHECK_FALSE(s.per_seed[0].windows[0].open_above);
  // 11 scan points, then each 20 ms bracket halved down to 1 ms: at most
  // ceil(log2 20) = 5 probes per boundary (the grid's midpoints round down),
  // at least 4; far fewer than the 200 of a 1 ms scan.
  CHECK(tissue.probes <= 11 + 2 * 5);
  CHECK(tissue.probes >= 11 + 2 * 4);
  REQUIRE(s.overall.size() == 1);
  CHECK(s.overall[0].lower_ms == 144);
}

TEST_CASE("windows per seed, several windows, windows at the scan's ends, and their union") {
  SyntheticTissue tissue{{{1, {{0, 125}, {210.4, 230}}}, {2, {{218, 260}}}, {3, {}}}};
  const WindowScan scan{100, 250, 10, 0.5};
  const WindowSearch s = search_vulnerable_window(scan, {1, 2, 3}, tissue.classifier());
  REQUIRE(s.per_seed.size() == 3);
  const auto& w1 = s.per_seed[0].windows;
  REQUIRE(w1.size() == 2);
  // Induced from the scan's start to 125; on the 0.5 ms grid from 120.
  CHECK(w1[0].lower_ms == 100);
  CHECK(w1[0].open_below);
  CHECK(w1[0].upper_ms == 125);
  CHECK(w1[1].lower_ms == 210.5);
  CHECK(w1[1].upper_ms == 230);
  const auto& w2 = s.per_seed[1].windows;
  REQUIRE(w2.size() == 1);
  CHECK(w2[0].lower_ms == 218);
  CHECK(w2[0].upper_ms == 250);
  CHECK(w2[0].open_above);
  CHECK(s.per_seed[2].windows.empty());
  // The union: [100, 125] and [210.5, 250].
  REQUIRE(s.overall.size() == 2);
  CHECK(s.overall[1].lower_ms == 210.5);
  CHECK(s.overall[1].upper_ms == 250);
}

TEST_CASE("a bad scan is refused") {
  CHECK_THROWS_WITH_AS(scan_intervals({100, 50, 10, 1}), "the scan's end is before its start", std::invalid_argument);
  CHECK_THROWS_WITH_AS(scan_intervals({100, 200, 0, 1}), "the scan's step must be > 0 ms", std::invalid_argument);
  CHECK(scan_intervals({100, 125, 10, 1}) == std::vector<double>{100, 110, 120});
}

TEST_CASE("the coupling interval counts from S1's last onset, and a manifest without S2 is named") {
  json m = json::parse(R"({"stimulus": [{"start_ms": 10, "period_ms": 300, "count": 4},
                                         {"start_ms": 1150}]})");
  CHECK(coupling_interval_ms(m, "the vulnerable-window search") == 1150 - (10 + 3 * 300));
  m["stimulus"][0].erase("count");
  CHECK_THROWS_WITH_AS(coupling_interval_ms(m, "the vulnerable-window search"),
                       "manifest: stimulus[0].count: an S1-S2 protocol needs a finite train: give count",
                       ManifestError);
  m["stimulus"].erase(1);
  CHECK_THROWS_AS(coupling_interval_ms(m, "the vulnerable-window search"), ManifestError);
  json none = json::object();
  CHECK(ensure_reentry_output(none));
  CHECK(none["output"]["reentry"]["every_ms"] == 2);
  CHECK_FALSE(ensure_reentry_output(none));
}

TEST_CASE("a run is classified from its summary: re-entry, S2 not captured, S2 captured") {
  // S2 at 200 ms is beat 1 (onsets 10, 200).
  json s = json::parse(R"({"status": "completed",
      "manifest": {"stimulus": [{"start_ms": 10}, {"start_ms": 200}]},
      "reentry": {"detected": false, "unreached_fraction_per_beat": [
        {"beat": 0, "fraction": 0.0, "myocytes": 100}, {"beat": 1, "fraction": 0.7, "myocytes": 100}]}})");
  CHECK(classify_summary(s, 200, 0.5) == S2Outcome::no_capture);  // 30 % reached < 50 %
  CHECK(classify_summary(s, 200, 0.25) == S2Outcome::no_reentry);
  s["reentry"]["detected"] = true;
  CHECK(classify_summary(s, 200, 0.5) == S2Outcome::reentry);
  s["status"] = "failed";
  CHECK(classify_summary(s, 200, 0.5) == S2Outcome::failed);
  CHECK(classify_summary(nullptr, 200, 0.5) == S2Outcome::failed);
}

// End to end on real tissue: a strand of 46 colman2013_caf myocytes (2 x 23,
// 3 mm, D_m 5 nS: 1.8 cm/s), S1 and S2 both at its bottom end. Re-entry is
// "detected" when activity outlasts the coupling interval after S2; here at
// short intervals the S1 wave is still travelling up the strand when S2
// comes (S2 itself is not captured), so it is detected while S1's arrival
// at the top (about 180 ms) is more than twice the interval after S1: a
// boundary near 74 ms that depends on the tissue's conduction, not on the
// search. The bisection's boundary must be the one a 1 ms scan of the same
// runs finds. About 30 runs of 0.1-0.3 s.
TEST_CASE("on a small strand, the bisection finds the boundary a 1 ms scan finds") {
  const auto dir = testing::scratch_dir("vulnerable_window");
  const json m = s1s2_strand();
  VulnerableWindowOptions options = in_process_search(dir);
  options.scan = {40, 200, 20, 1};
  const VulnerableWindowResult found = run_vulnerable_window(m, options);
  CHECK(found.reentry_output_added);
  REQUIRE(found.search.per_seed.size() == 1);
  const auto& windows = found.search.per_seed[0].windows;
  REQUIRE(windows.size() == 1);
  CHECK(windows[0].open_below);
  const double upper = windows[0].upper_ms;
  // The coarse scan's bracket of the boundary, scanned at 1 ms (the runs the
  // bisection made are reused: same manifests, same folders).
  const double bracket_low = 40 + 20 * std::floor((upper - 40) / 20);
  VulnerableWindowOptions fine = options;
  fine.scan = {bracket_low, bracket_low + 20, 1, 1};
  const VulnerableWindowResult scanned = run_vulnerable_window(m, fine);
  CHECK(scanned.reused >= 4);  // the bisection's probes and the bracket's ends
  REQUIRE(scanned.search.per_seed[0].windows.size() == 1);
  const double fine_upper = scanned.search.per_seed[0].windows[0].upper_ms;
  CHECK(std::abs(upper - fine_upper) <= 1);
  // Plausible against the strand: S1 reaches the top about 180 ms after S1.
  CHECK(upper > 60);
  CHECK(upper < 100);
  // Above the boundary and below the refractory period S2 is not captured;
  // at 200 ms it is, and activity after it is shorter than the interval.
  std::map<double, S2Outcome> outcome;
  for (const auto& r : found.search.results) outcome[r.probe.interval_ms] = r.outcome;
  CHECK(outcome.at(120) == S2Outcome::no_capture);
  CHECK(outcome.at(200) == S2Outcome::no_reentry);
  for (const char* file : {"vulnerable_window.csv", "vulnerable_window.json", "vulnerable_window.png", "report.html"})
    CHECK(std::filesystem::exists(options.out / file));
  const json j = json::parse(testing::read_file(options.out / "vulnerable_window.json"));
  CHECK(j["per_seed"][0]["windows"][0]["upper_ms"] == upper);
  CHECK(j.contains("note"));
}

TEST_CASE("a search whose runs end before S2 is refused, naming duration_ms") {
  json m = json::parse(R"({"fibrodem": 1, "name": "short", "duration_ms": 100,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.05, "length_mm": 0.5},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013_caf"}},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000},
                 {"target": "myocyte", "start_ms": 200, "duration_ms": 2, "amplitude_pA": 4000}]})");
  VulnerableWindowOptions options;
  options.out = testing::scratch_dir("vulnerable_window_short");
  CHECK_THROWS_WITH_AS(run_vulnerable_window(m, options),
                       "manifest: duration_ms: the run must last past S2 (stimulus[1].start_ms 200 ms), got 100 ms",
                       ManifestError);
}

TEST_CASE("the command refuses a manifest without S2, naming it") {
  const auto dir = testing::scratch_dir("vulnerable_window_cli");
  json m = testing::passive_cell_manifest();
  std::ofstream(dir / "one.json") << m.dump();
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem vulnerable-window " +
                              (dir / "one.json").string() + " --out " + (dir / "out").string() + " 2> " +
                              (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(testing::read_file(dir / "err.txt").find("stimulus") != std::string::npos);
}

TEST_CASE("the search runs with mechanics on: a small electromechanical sheet, each run classified") {
  // The strand of the case above, 0.1 mm wide (4 columns), with Rice
  // myofilaments and the DEM (the sheet is bonded): three intervals, each a
  // run with mechanics that completes and is classified as on the strand
  // without mechanics (the DEM does not feed back to V without
  // mechano_electric_feedback; with it, the stretch-activated current is on).
  const auto dir = testing::scratch_dir("vulnerable_window_em");
  json m = s1s2_strand();
  m["name"] = "em_strand";
  m["effects"] = {"electrophysiology", "coupling", "contraction", "mechanics", "mechano_electric_feedback"};
  m["tissue"]["width_mm"] = 0.1;
  m["cells"]["myocyte"]["myofilament"] = "rice";
  VulnerableWindowOptions options = in_process_search(dir);
  options.scan = {60, 200, 70, 70};  // 60, 130, 200 ms; the resolution leaves no bisection
  const VulnerableWindowResult found = run_vulnerable_window(m, options);
  REQUIRE(found.search.results.size() == 3);
  std::map<double, S2Outcome> outcome;
  for (const auto& r : found.search.results) {
    CAPTURE(r.error);
    CHECK(r.outcome != S2Outcome::failed);
    outcome[r.probe.interval_ms] = r.outcome;
  }
  // As on the strand without mechanics: re-entry below its boundary (60-100
  // ms), S2 not captured at 130 ms, captured without re-entry at 200 ms.
  CHECK(outcome.at(60) == S2Outcome::reentry);
  CHECK(outcome.at(130) == S2Outcome::no_capture);
  CHECK(outcome.at(200) == S2Outcome::no_reentry);
  const json summary = json::parse(testing::read_file(options.out / "runs" / "ci_200ms_seed_1" / "summary.json"));
  CHECK(summary.contains("peak_strain"));
}
