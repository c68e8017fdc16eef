// A/B comparison: the table's differences, and traces on a common time base.
#include <doctest/doctest.h>

#include <cmath>

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
