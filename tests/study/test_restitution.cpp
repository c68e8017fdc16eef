// `fibrodem restitution`: S1-S2 APD restitution and the ERP
// (study/restitution.hpp), on a table with a known answer and on the
// Courtemanche 1998 model, control and chronic-AF, against Myokit.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "model/plugin_registry.hpp"
#include "study/restitution.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

CsvTable biomarker_table(const std::vector<std::vector<std::string>>& rows) {
  CsvTable t;
  t.header = {"cell", "type", "beat", "activation_ms", "rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms", "apd50_ms"};
  t.rows = rows;
  return t;
}

}  // namespace

TEST_CASE("a restitution point: medians over the captured cells, local DI, S2 too small is not captured") {
  // Beats 1 (before the last S1), 2 (last S1), 3 (S2). Cell 0 fires on S2;
  // cell 1 only depolarises (amplitude 30 of S1's 100 mV); cell 2 was not
  // excited by S1 (no APD90) and is not measured; cell 3 is a fibroblast.
  const CsvTable t = biomarker_table({
      {"0", "myocyte", "2", "1010", "-80", "20", "200", "150", "80"},
      {"0", "myocyte", "3", "1260", "-79", "18", "150", "140", "60"},
      {"1", "myocyte", "2", "1012", "-80", "20", "210", "150", "85"},
      {"1", "myocyte", "3", "1262", "-79", "-49", "20", "5", "10"},
      {"2", "myocyte", "2", "1013", "-80", "-70", "", "1", ""},
      {"3", "fibroblast", "2", "1010", "-30", "-20", "50", "1", "20"},
  });
  const RestitutionPoint p = restitution_point(t, 2, 3, {}, 0.5);
  CHECK(p.cells_measured == 2);
  CHECK(p.cells_captured == 1);
  CHECK(p.captured);  // 1 of 2 >= 0.5
  CHECK(p.s2_apd90_ms == 150);
  CHECK(p.s2_apd50_ms == 60);
  CHECK(p.s1_apd90_ms == 200);
  CHECK(p.di_ms == 1260 - (1010 + 200));  // S2's activation minus the end of the S1 action potential
  CHECK_FALSE(restitution_point(t, 2, 3, {}, 0.6).captured);
  // Cells chosen by index: the fibroblast alone.
  const RestitutionPoint f = restitution_point(t, 2, 3, {3}, 0.5);
  CHECK(f.cells_measured == 1);
  CHECK(f.cells_captured == 0);

  // S2 cut the last S1 beat short (APD90 unmeasured): the beat before stands in.
  const CsvTable cut = biomarker_table({
      {"0", "myocyte", "1", "10", "-80", "20", "200", "150", "80"},
      {"0", "myocyte", "2", "1010", "-80", "20", "", "150", ""},
      {"0", "myocyte", "3", "1205", "-60", "10", "120", "100", "50"},
  });
  const RestitutionPoint c = restitution_point(cut, 2, 3, {}, 0.5);
  CHECK(c.captured);  // amplitude 70 >= half of 100
  CHECK(c.s1_apd90_ms == 200);
  CHECK(c.di_ms == 1205 - (1010 + 200));
}

// The Courtemanche-Ramirez-Nattel model, control (paced_1hz) and chronic AF
// (courtemanche1999_caf: g_to x0.5, g_CaL x0.3, g_Kur x0.5), 3 S1 beats at
// 1 Hz from each variant's initial state (2000 pA x 2 ms), then S2.
//
// Expected values: Myokit 1.39.3 (git f60e118e), myokit/models
// courtemanche-1998.mmt with the same remodelling, I_stim removed from dK_i/dt
// (the CellML's form, as here), stimulus -2000 pA x 2 ms, the same initial
// states, CVODE rtol 1e-8 atol 1e-10 and a 0.01 ms maximum step, V logged
// every 0.005 ms; APD from the time of max dV/dt to the last downward
// crossing of V_peak - X % (V_peak - V at the beat's onset), as
// measure/biomarkers.hpp defines it. With CVODE at the same tolerances the two
// agree to 0.005 ms; 0.02 ms allows for Myokit's 0.005 ms sampling.
TEST_CASE("courtemanche1999_caf and its control: S1-S2 restitution and ERP as Myokit computes them") {
  struct Expected {
    double interval_ms, apd90_ms, apd50_ms;
  };
  struct Case {
    const char* variant;
    std::vector<Expected> points;
  };
  const std::vector<Case> cases = {
      {"courtemanche1999_caf",
       {{1000, 193.18, 71.76}, {600, 180.69, 68.88}, {400, 166.52, 63.65}, {300, 151.73, 62.60}, {250, 144.80, 61.19},
        {200, 125.83, 65.96}}},
      {"paced_1hz", {{1000, 291.40, 164.59}, {600, 267.03, 134.85}, {400, 212.05, 70.41}, {300, 152.22, 74.56}}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.variant);
    const json m = {
        {"fibrodem", 1},
        {"name", "crn_s1s2"},
        {"duration_ms", 2810},
        {"tissue", {{"builder", "single_cell"}, {"type", "myocyte"}}},
        {"cells", {{"myocyte", {{"model", "courtemanche"}, {"variant", c.variant}}}}},
        {"stimulus", json::array({{{"target", "myocyte"}, {"start_ms", 10}, {"duration_ms", 2}, {"amplitude_pA", 2000},
                                   {"period_ms", 1000}, {"count", 3}},
                                  {{"target", "myocyte"}, {"start_ms", 2410}, {"duration_ms", 2}, {"amplitude_pA", 2000}}})},
        {"solver", {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-10}}},
        {"output", {{"report", false}}},
    };
    RestitutionOptions options;
    options.out = testing::scratch_dir(std::string("restitution_") + c.variant);
    options.runner = InProcessRunner{PluginRegistry::search_path_beside(FIBRODEM_BINARY_DIR)};
    options.jobs = 2;
    for (const auto& e : c.points) options.intervals_ms.push_back(e.interval_ms);
    options.erp_resolution_ms = 0;
    const RestitutionResult r = run_restitution(m, options);
    REQUIRE(r.points.size() == c.points.size());
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      CAPTURE(c.points[k].interval_ms);
      CHECK(r.points[k].interval_ms == c.points[k].interval_ms);
      CHECK(r.points[k].captured);
      CHECK(std::abs(r.points[k].s2_apd90_ms - c.points[k].apd90_ms) <= 0.02);
      CHECK(std::abs(r.points[k].s2_apd50_ms - c.points[k].apd50_ms) <= 0.02);
    }
  }
}

// The ERP of the chronic-AF cell. Myokit (as above) gives the S2 response's
// amplitude over the S1 response's: 0.495 at 189 ms, 0.503 at 190 ms, so with
// the capture threshold of one half the ERP (longest interval not captured)
// is 189 ms. The bisection from a 10 ms scan must land there.
TEST_CASE("courtemanche1999_caf: the ERP found by bisection is Myokit's") {
  const json m = {
      {"fibrodem", 1},
      {"name", "crn_erp"},
      {"duration_ms", 2610},
      {"tissue", {{"builder", "single_cell"}, {"type", "myocyte"}}},
      {"cells", {{"myocyte", {{"model", "courtemanche"}, {"variant", "courtemanche1999_caf"}}}}},
      {"stimulus", json::array({{{"target", "myocyte"}, {"start_ms", 10}, {"duration_ms", 2}, {"amplitude_pA", 2000},
                                 {"period_ms", 1000}, {"count", 3}},
                                {{"target", "myocyte"}, {"start_ms", 2210}, {"duration_ms", 2}, {"amplitude_pA", 2000}}})},
      {"solver", {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-10}}},
      {"output", {{"report", false}}},
  };
  RestitutionOptions options;
  options.out = testing::scratch_dir("restitution_erp");
  options.runner = InProcessRunner{PluginRegistry::search_path_beside(FIBRODEM_BINARY_DIR)};
  options.jobs = 2;
  options.intervals_ms = {200, 180};
  const RestitutionResult r = run_restitution(m, options);
  REQUIRE(r.erp_ms.has_value());
  CHECK(*r.erp_ms == 189);
  // Every interval run is captured exactly when it is above the ERP.
  for (const auto& p : r.points) CHECK(p.captured == (p.interval_ms > 189));
}

TEST_CASE("restitution refuses a manifest without S2 or a run that ends before it") {
  json m = testing::passive_cell_manifest();
  RestitutionOptions options;
  options.out = testing::scratch_dir("restitution_bad");
  CHECK_THROWS_AS(run_restitution(m, options), ManifestError);
  m["stimulus"] = json::array(
      {{{"target", "fibroblast"}, {"start_ms", 10}, {"duration_ms", 1}, {"amplitude_pA", 100}, {"period_ms", 100}},
       {{"target", "fibroblast"}, {"start_ms", 150}, {"duration_ms", 1}, {"amplitude_pA", 100}}});
  CHECK_THROWS_WITH_AS(run_restitution(m, options),
                       "manifest: stimulus[0].count: an S1-S2 protocol needs a finite train: give count", ManifestError);
  m["stimulus"][0]["count"] = 2;
  m["duration_ms"] = 100;
  CHECK_THROWS_AS(run_restitution(m, options), ManifestError);
}
