// A/B comparison: the table's differences, and traces on a common time base.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sys/wait.h>

#include "compare/ab_comparison.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
RunRecord labelled(std::string label, std::vector<std::string> columns = {}) {
  RunRecord r;
  r.label = std::move(label);
  r.samples.resize(columns.size());
  r.columns = std::move(columns);
  return r;
}
}  // namespace

TEST_CASE("the comparison table holds A, B, their difference and relative difference") {
  RunRecord a = labelled("A"), b = labelled("B");
  a.mean_biomarkers = {{"myocyte", {{"rmp_mV", -80.0}, {"apo_mV", 20.0}, {"apd90_ms", 300.0}, {"dvdt_max_mV_per_ms", 200.0}}}};
  b.mean_biomarkers = {{"myocyte", {{"rmp_mV", -76.0}, {"apo_mV", 20.0}, {"apd90_ms", 270.0}, {"dvdt_max_mV_per_ms", nullptr}}}};
  const auto rows = compare_biomarkers(a, b);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0].metric == "rmp_mV");
  CHECK(rows[0].diff() == doctest::Approx(4.0));
  CHECK(rows[0].relative_diff() == doctest::Approx(0.05));
  CHECK(rows[2].relative_diff() == doctest::Approx(-0.1));
  CHECK(std::isnan(rows[3].b));
  const std::string md = comparison_markdown(a, b);
  CHECK(md.find("| myocyte | apd90_ms | 300.00 | 270.00 | -30.00 | -10.0 % |") != std::string::npos);
  CHECK(md.find("n/a") != std::string::npos);
}

TEST_CASE("traces of both runs are interpolated onto a common time base") {
  // A sampled every 1 ms on [0, 10], B every 0.5 ms on [2, 12]: common span
  // [2, 10] at 0.5 ms; both are straight lines, so interpolation is exact.
  RunRecord a = labelled("A", {"V_0"});
  RunRecord b = labelled("B", {"V_0", "V_1"});
  for (int k = 0; k <= 10; ++k) {
    a.times_ms.push_back(k);
    a.samples[0].push_back(2.0 * k);
  }
  for (int k = 4; k <= 24; ++k) {
    b.times_ms.push_back(0.5 * k);
    b.samples[0].push_back(-0.5 * k);
    b.samples[1].push_back(0);
  }
  const auto dir = testing::scratch_dir("compare");
  write_comparison(a, b, dir);
  std::istringstream csv(testing::read_file(dir / "traces.csv"));
  std::string line;
  std::getline(csv, line);
  CHECK(line == "t_ms,A:V_0,B:V_0");
  int rows = 0;
  while (std::getline(csv, line)) {
    double t, va, vb;
    char comma;
    std::istringstream row(line);
    row >> t >> comma >> va >> comma >> vb;
    CHECK(va == doctest::Approx(2.0 * t));
    CHECK(vb == doctest::Approx(-t));
    ++rows;
  }
  CHECK(rows == 17);  // 2, 2.5, ..., 10
  CHECK(std::filesystem::exists(dir / "comparison.md"));
  CHECK(std::filesystem::exists(dir / "comparison.csv"));
}

TEST_CASE("compare --seeds: A and B on the same tissues, paired differences of known sign, checked by hand") {
  const auto dir = testing::scratch_dir("compare_seeds");
  // A small in-series tissue; passive fibroblasts (resting near -58 mV on
  // their own) are pulled towards the myocytes' -75 mV the more they are
  // coupled: raising D_f from 0.5 to 4 nS must lower the fibroblasts' RMP
  // (V at the onset of the beat, 10 ms in).
  std::ofstream(dir / "m.json") << R"({"fibrodem": 1, "name": "pairs", "duration_ms": 20, "seed": 3,
    "tissue": {"builder": "in_series", "width_mm": 0.2, "height_mm": 0.8, "fm_ratio": 0.3},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_f_nS": 1},
    "stimulus": [{"target": {"y_min_frac": 0.8, "type": "myocyte"}, "start_ms": 10, "duration_ms": 2, "amplitude_pA": 3000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"traces": {"cells": [0, 1], "variables": ["V"], "every_ms": 0.5}}})";
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem compare --quiet " + (dir / "m.json").string() +
                              " --a coupling.D_f_nS=0.5 --b coupling.D_f_nS=4 --seeds 3 --out " + (dir / "out").string() +
                              " > /dev/null 2>&1";
  REQUIRE(std::system(command.c_str()) == 0);
  // By hand from the six runs' summaries: the mean difference of fibroblast RMP.
  double mean = 0;
  for (int seed : {3, 4, 5}) {
    const auto summary = [&](const char* v) {
      return json::parse(testing::read_file(dir / "out" / ("seed_" + std::to_string(seed)) / v / "summary.json"));
    };
    CHECK(summary("A")["manifest"]["seed"] == seed);
    mean += (summary("B")["mean_biomarkers"]["fibroblast"]["rmp_mV"].get<double>() -
             summary("A")["mean_biomarkers"]["fibroblast"]["rmp_mV"].get<double>()) / 3;
  }
  std::istringstream csv(testing::read_file(dir / "out" / "paired.csv"));
  std::string line, row;
  std::getline(csv, line);
  CHECK(line == "metric,pairs,a_mean,b_mean,b_minus_a_mean,b_minus_a_sd,ci95_low,ci95_high,t,p");
  while (std::getline(csv, line))
    if (line.rfind("fibroblast_rmp_mV,", 0) == 0) row = line;
  REQUIRE(!row.empty());
  std::vector<double> cells;
  std::stringstream cells_text(row.substr(row.find(',') + 1));
  for (std::string c; std::getline(cells_text, c, ',');) cells.push_back(std::stod(c));
  CHECK(cells[0] == 3);                                        // pairs
  CHECK(cells[3] == doctest::Approx(mean).epsilon(1e-12));     // B - A
  CHECK(cells[3] < -1.0);                                      // the known sign, well clear of zero
  CHECK(cells[6] < 0);                                         // the whole 95 % CI below zero
  CHECK(cells[8] < 0.05);                                      // p
  CHECK(std::filesystem::exists(dir / "out" / "traces.png"));  // A and B overlaid (first tissue)
  CHECK(testing::read_file(dir / "out" / "paired.md").find("paired t-test") != std::string::npos);
}

TEST_CASE("compare checks A and B before running either: a bad B stops it with nothing of A run") {
  const auto dir = testing::scratch_dir("compare_bad_b");
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 5;
  std::ofstream(dir / "m.json") << m.dump();
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem compare --quiet " + (dir / "m.json").string() +
                              " --b cells.fibroblast.parameters.no_such_parameter=1 --out " + (dir / "out").string() +
                              " > " + (dir / "stdout.txt").string() + " 2> " + (dir / "stderr.txt").string();
  const int status = std::system(command.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 2);  // a manifest error
  const std::string err = testing::read_file(dir / "stderr.txt");
  CAPTURE(err);
  CHECK(err.find("manifest: B: cells.fibroblast.parameters.no_such_parameter: ") != std::string::npos);
  // The path once: "B: PATH: PATH: ..." said it twice.
  CHECK(err.find("no_such_parameter: cells.") == std::string::npos);
  CHECK(!std::filesystem::exists(dir / "out" / "A" / "summary.json"));  // A never ran
}
