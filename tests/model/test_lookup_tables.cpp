// solver.lookup_tables: voltage_only gate rates from a table in V (linear
// interpolation every 0.05 mV, openCARP LIMPET style).
//  (a) the table's a, b match the model's own at random V;
//  (b) the model, asked to skip its voltage_only gates, changes nothing else;
//  (c) tables off is the exact model, bit for bit;
//  (d) one colman beat with tables agrees with the table-free beat.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <string>
#include <vector>

#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "model/simd.hpp"
#include "model/voltage_table.hpp"
#include "run/simulation.hpp"
#include "scene/scene.hpp"

namespace {

using fibrodem::Population;

std::shared_ptr<const fibrodem::CellModel> load(const std::string& name) {
  static fibrodem::PluginRegistry registry;
  return registry.load(name);
}

// n cells at the model's defaults, V spread over [v_lo, v_hi] at random.
Population random_block(const std::string& model, std::size_t n, double v_lo, double v_hi, unsigned seed) {
  Population pop;
  pop.model = load(model);
  for (const auto& p : pop.info().parameters) pop.params.push_back(p.default_value);
  for (const auto& s : pop.info().states) pop.initial_state.push_back(s.initial);
  pop.voltage_state = pop.info().voltage_state;
  pop.cells.resize(n);
  pop.reset();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> V(v_lo, v_hi);
  for (std::size_t c = 0; c < n; ++c) pop.state(pop.voltage_state, c) = V(rng);
  return pop;
}

fibrodem::json colman_beat(bool tables) {
  fibrodem::json m = {
      {"fibrodem", 1},
      {"name", "colman_lut"},
      {"duration_ms", 1000.0},
      {"tissue", {{"builder", "single_cell"}, {"type", "myocyte"}}},
      {"cells", {{"myocyte", {{"model", "colman"}}}}},
      {"stimulus", {{{"target", "myocyte"}, {"start_ms", 10}, {"duration_ms", 2}, {"amplitude_pA", 2000}}}},
      {"solver", {{"method", "rush_larsen"}, {"dt_ms", 0.02}}},
      {"output", {{"traces", {{"cells", {0}}, {"variables", {"V", "Ca_i"}}, {"every_ms", 0.5}}}}},
  };
  m["solver"]["lookup_tables"] = tables;  // explicit: unset means on for rush_larsen
  return m;
}

}  // namespace

TEST_CASE("lookup tables: which gates are tabulated") {
  Population colman = random_block("colman", 1, -80, -80, 1);
  REQUIRE(colman.use_lookup_table());
  std::vector<std::string> names;
  for (int k : colman.table->gates()) names.push_back(colman.info().states[k].name);
  CHECK(names == std::vector<std::string>{"m", "h", "j", "d", "f", "xr", "xs", "ito_r", "ito_s", "ikur_a",
                                          "ikur_i"});
  CHECK(colman.table->points() == 4001);  // -120 .. +80 mV every 0.05 mV
  Population crn = random_block("courtemanche", 1, -80, -80, 1);
  REQUIRE(crn.use_lookup_table());
  CHECK(crn.table->gates().size() == 11);
  Population passive = random_block("passive_fibroblast", 1, -50, -50, 1);
  CHECK_FALSE(passive.use_lookup_table());  // no voltage_only gate: no table
  CHECK(passive.table == nullptr);
}

TEST_CASE("lookup tables: tabulated a, b match the model's own at random V") {
  // Linear interpolation over h = 0.05 mV errs by at most h^2/8 |f''|. The
  // steepest exponential of these models (exp(0.35 V) in CRN's h beta) has
  // |f''/f| = 0.35^2 /mV^2, so the relative error is below 3.1e-4 * 0.1225 ~ 4e-5;
  // tolerance 2e-4 relative (plus 1e-12 /ms absolute, for rates that vanish). The one exception is the piecewise I_Na h, j rates at
  // V = -40 mV (a jump, not interpolable): the interval around it is excluded.
  for (const std::string model : {"colman", "courtemanche"}) {
    CAPTURE(model);
    Population exact = random_block(model, 5000, -119.9, 79.9, 42);
    Population tabled = exact;
    REQUIRE(tabled.use_lookup_table());
    exact.evaluate(0.0);
    tabled.evaluate(0.0);
    const std::size_t n = exact.size();
    double worst = 0;
    for (int k : tabled.table->gates()) {
      for (std::size_t c = 0; c < n; ++c) {
        const double V = exact.state(exact.voltage_state, c);
        if (std::fabs(V + 40.0) < 0.05) continue;
        for (auto arr : {&Population::a, &Population::b}) {
          const double want = (exact.*arr)[k * n + c], got = (tabled.*arr)[k * n + c];
          const double err = std::fabs(got - want) / (std::fabs(want) + 1e-12 / 2e-4);
          worst = std::max(worst, err);
          if (std::fabs(got - want) > 2e-4 * std::fabs(want) + 1e-12) {
            CAPTURE(exact.info().states[k].name);
            CAPTURE(V);
            CHECK(got == doctest::Approx(want).epsilon(2e-4));
          }
        }
      }
    }
    MESSAGE(model << ": worst relative error of a table rate " << worst);
    CHECK(tabled.table->clamp_count() == 0);
  }
}

TEST_CASE("lookup tables: skipping voltage_only gates changes nothing else, tables off is exact") {
  for (const std::string model : {"colman", "courtemanche"}) {
    CAPTURE(model);
    Population full = random_block(model, 700, -100, 60, 7);
    full.evaluate(0.0);
    // The model itself, skip flag off, straight through its BlockView.
    Population direct = full;
    std::fill(direct.a.begin(), direct.a.end(), 0.0);
    std::fill(direct.b.begin(), direct.b.end(), 0.0);
    direct.model->evaluate(direct.view(), 0.0);
    CHECK(direct.a == full.a);  // tables off: Population::evaluate is the bare model
    CHECK(direct.b == full.b);
    CHECK(direct.outputs == full.outputs);
    // Skip flag on: every state that is not voltage_only, and every output, bit for bit.
    Population skipped = full;
    std::fill(skipped.a.begin(), skipped.a.end(), -7.0);
    std::fill(skipped.b.begin(), skipped.b.end(), -7.0);
    fibrodem::BlockView v = skipped.view();
    v.skip_voltage_only_gates = true;
    skipped.model->evaluate(v, 0.0);
    const std::size_t n = full.size();
    for (std::size_t k = 0; k < full.n_states(); ++k) {
      const bool vo = full.info().states[k].voltage_only;
      CAPTURE(full.info().states[k].name);
      const std::vector<double> fa(full.a.begin() + k * n, full.a.begin() + (k + 1) * n);
      const std::vector<double> sa(skipped.a.begin() + k * n, skipped.a.begin() + (k + 1) * n);
      if (vo) CHECK(sa == std::vector<double>(n, -7.0));  // left unwritten: the exp() calls were skipped
      else CHECK(sa == fa);
    }
    CHECK(skipped.outputs == full.outputs);
  }
  // A whole run: no lookup_tables key and lookup_tables = false are the same run.
  auto off = colman_beat(false);
  fibrodem::Simulation a(fibrodem::parse_scene(off));
  a.run();
  off["solver"]["lookup_tables"] = false;
  fibrodem::Simulation b(fibrodem::parse_scene(off));
  b.run();
  CHECK(a.trace("V", 0) == b.trace("V", 0));
  CHECK(a.trace("Ca_i", 0) == b.trace("Ca_i", 0));
}

TEST_CASE("lookup tables: a colman beat agrees with the table-free beat") {
  // Rates off by < ~4e-5 relative (test above) move the action potential by far
  // less than the dt = 0.02 ms discretisation error itself. Tolerances: APD90
  // 0.05 ms (2.5 steps), APO and RMP 0.01 mV, peak Ca_i 0.1 %.
  fibrodem::Simulation exact(fibrodem::parse_scene(colman_beat(false)));
  exact.run();
  fibrodem::Simulation tabled(fibrodem::parse_scene(colman_beat(true)));
  tabled.run();
  REQUIRE(exact.biomarkers().size() == 1);
  REQUIRE(tabled.biomarkers().size() == 1);
  const auto& e = exact.biomarkers().front();
  const auto& t = tabled.biomarkers().front();
  MESSAGE(std::setprecision(10) << "APD90 " << e.apd90_ms << " vs " << t.apd90_ms << " ms; APO " << e.apo_mV << " vs " << t.apo_mV
                   << " mV; RMP " << e.rmp_mV << " vs " << t.rmp_mV);
  CHECK(std::fabs(t.apd90_ms - e.apd90_ms) <= 0.05);
  CHECK(std::fabs(t.apo_mV - e.apo_mV) <= 0.01);
  CHECK(std::fabs(t.rmp_mV - e.rmp_mV) <= 0.01);
  const auto& ce = exact.trace("Ca_i", 0);
  const auto& ct = tabled.trace("Ca_i", 0);
  CHECK(*std::max_element(ct.begin(), ct.end()) ==
        doctest::Approx(*std::max_element(ce.begin(), ce.end())).epsilon(1e-3));
  CHECK(exact.trace("V", 0) != tabled.trace("V", 0));  // the tables were used
}

TEST_CASE("lookup tables are on by default for fixed steps, off for CVODE, and follow the manifest") {
  fibrodem::json m = colman_beat(false);
  m["solver"].erase("lookup_tables");
  CHECK(fibrodem::parse_scene(m).solver.use_lookup_tables());
  m["solver"]["method"] = "cvode";
  CHECK_FALSE(fibrodem::parse_scene(m).solver.use_lookup_tables());
  m["solver"]["lookup_tables"] = true;
  CHECK(fibrodem::parse_scene(m).solver.use_lookup_tables());
  m["solver"] = {{"method", "rush_larsen"}, {"lookup_tables", false}};
  CHECK_FALSE(fibrodem::parse_scene(m).solver.use_lookup_tables());
}

TEST_CASE("lookup tables: Rush-Larsen columns advance the gates as exp(b dt) would, and count V off the table") {
  // 2 lane groups and a narrow tail; V across the table, 2 cells below it and 1 NaN.
  const std::size_t n = 2 * fibrodem::simd::kLanes + 3;
  Population pop = random_block("colman", n, -100, 60, 11);
  pop.state(pop.voltage_state, 0) = -150;  // below the table: clamped to its first row
  pop.state(pop.voltage_state, 5) = -121;
  pop.state(pop.voltage_state, n - 1) = std::nan("");
  REQUIRE(pop.use_lookup_table());
  const double dt = 0.01;
  const auto rl = pop.table->with_rush_larsen_step(dt);
  REQUIRE(rl != nullptr);
  pop.evaluate(0.0);  // the table's a, b (skip_voltage_only_gates + fill): the reference update
  std::vector<double> y = pop.y;
  rl->advance_gates(y.data(), n, pop.voltage(), 0, n);
  CHECK(rl->clamp_count() == 3);
  for (int k : rl->gates())
    for (std::size_t c = 1; c + 1 < n; ++c) {
      if (c == 5) continue;
      const double a = pop.a[k * n + c], b = pop.b[k * n + c], y0 = pop.y[k * n + c];
      const double exact = -a / b + (y0 + a / b) * std::exp(b * dt);
      // Interpolating exp(b dt) instead of b: second order in the 0.05 mV spacing.
      CHECK(y[k * n + c] == doctest::Approx(exact).epsilon(1e-6));
    }
}
