// The process-wide cache of lookup-table rows (model/voltage_table_cache.hpp):
//  (a) a run whose tables come from the cache gives byte-identical traces and
//      biomarkers to one that sampled them afresh, and cached rows are the
//      freshly sampled ones bit for bit;
//  (b) any change to what the rows are sampled from (a parameter by one ulp,
//      the Rush-Larsen dt, the model's origin) misses the cache;
//  (c) the cache stays within its byte budget over many parameter sets;
//  (d) each table counts its own clamps, though the rows are shared;
//  (e) threads building the same table at once end up sharing one copy.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "model/voltage_table.hpp"
#include "model/voltage_table_cache.hpp"
#include "run/simulation.hpp"
#include "scene/scene.hpp"

namespace {

using fibrodem::Population;
using fibrodem::VoltageTableCache;

Population colman_cell() {
  static fibrodem::PluginRegistry registry;
  Population pop;
  pop.model = registry.load("colman");
  const auto* record = registry.record("colman");
  REQUIRE(record != nullptr);
  pop.model_origin = record->file.string() + " sha256:" + record->sha256;
  for (const auto& p : pop.info().parameters) pop.params.push_back(p.default_value);
  for (const auto& s : pop.info().states) pop.initial_state.push_back(s.initial);
  pop.voltage_state = pop.info().voltage_state;
  pop.cells.resize(1);
  pop.reset();
  return pop;
}

bool same_bytes(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

fibrodem::json colman_beat() {
  return {
      {"fibrodem", 1},
      {"name", "colman_cache"},
      {"duration_ms", 600.0},
      {"tissue", {{"builder", "single_cell"}, {"type", "myocyte"}}},
      {"cells", {{"myocyte", {{"model", "colman"}}}}},
      {"stimulus", {{{"target", "myocyte"}, {"start_ms", 10}, {"duration_ms", 2}, {"amplitude_pA", 2000}}}},
      {"solver", {{"method", "rush_larsen"}, {"dt_ms", 0.02}, {"lookup_tables", true}}},
      {"output", {{"traces", {{"cells", {0}}, {"variables", {"V", "Ca_i", "m"}}, {"every_ms", 0.5}}}}},
  };
}

}  // namespace

TEST_CASE("table cache: a run with cached tables is byte-identical to one with fresh tables") {
  auto& cache = VoltageTableCache::instance();
  cache.clear();
  fibrodem::Simulation fresh(fibrodem::parse_scene(colman_beat()));
  fresh.run();
  const long long misses = cache.misses(), hits = cache.hits();
  CHECK(misses == 2);  // the a, b rows and their Rush-Larsen columns, both sampled
  CHECK(hits == 0);
  fibrodem::Simulation cached(fibrodem::parse_scene(colman_beat()));
  cached.run();
  CHECK(cache.misses() == misses);  // nothing sampled again
  CHECK(cache.hits() == hits + 2);
  for (const char* v : {"V", "Ca_i", "m"}) {
    INFO(v);
    CHECK(same_bytes(fresh.trace(v, 0), cached.trace(v, 0)));
  }
  REQUIRE(fresh.biomarkers().size() == 1);
  REQUIRE(cached.biomarkers().size() == 1);
  const auto& f = fresh.biomarkers().front();
  const auto& c = cached.biomarkers().front();
  CHECK(same_bytes({f.activation_ms, f.rmp_mV, f.apo_mV, f.apd50_ms, f.apd90_ms, f.dvdt_max_mV_per_ms},
                   {c.activation_ms, c.rmp_mV, c.apo_mV, c.apd50_ms, c.apd90_ms, c.dvdt_max_mV_per_ms}));
  CHECK(std::isfinite(f.apd90_ms));  // a real beat was compared
}

TEST_CASE("table cache: cached rows are the freshly sampled rows, bit for bit") {
  auto& cache = VoltageTableCache::instance();
  cache.clear();
  Population pop = colman_cell();
  const auto first = fibrodem::VoltageTable::build(pop);
  REQUIRE(first != nullptr);
  const auto first_rl = first->with_rush_larsen_step(0.02);
  REQUIRE(first_rl != nullptr);
  const auto again = fibrodem::VoltageTable::build(pop);
  CHECK(again->rows() == first->rows());  // the same shared object
  CHECK(again != first);                  // in a table of its own
  cache.clear();                          // sampled afresh below
  const auto fresh = fibrodem::VoltageTable::build(pop);
  const auto fresh_rl = fresh->with_rush_larsen_step(0.02);
  CHECK(fresh->rows() != first->rows());
  CHECK(same_bytes(*fresh->rows()->rows, *first->rows()->rows));
  CHECK(same_bytes(*fresh_rl->rows()->rows, *first_rl->rows()->rows));
  CHECK(same_bytes(fresh_rl->rows()->rl_rows, first_rl->rows()->rl_rows));
  // The Rush-Larsen rows hold the a, b rows they were built from, not a copy.
  CHECK(fresh_rl->rows()->rows == fresh->rows()->rows);
}

TEST_CASE("table cache: any change to what was sampled misses the cache") {
  auto& cache = VoltageTableCache::instance();
  cache.clear();
  Population pop = colman_cell();
  const auto base = fibrodem::VoltageTable::build(pop);
  REQUIRE(base != nullptr);
  const auto base_rl = base->with_rush_larsen_step(0.02);

  SUBCASE("a parameter one ulp away") {
    Population other = pop;
    other.params[0] = std::nextafter(other.params[0], 1e300);
    CHECK(fibrodem::VoltageTable::build(other)->rows() != base->rows());
  }
  SUBCASE("an initial state one ulp away") {
    Population other = pop;
    const int k = base->gates().front();
    other.initial_state[k] = std::nextafter(other.initial_state[k], 1e300);
    CHECK(fibrodem::VoltageTable::build(other)->rows() != base->rows());
  }
  SUBCASE("another table range or spacing") {
    CHECK(fibrodem::VoltageTable::build(pop, -120, 80, 0.1)->rows() != base->rows());
    CHECK(fibrodem::VoltageTable::build(pop, -130, 80, 0.05)->rows() != base->rows());
  }
  SUBCASE("another Rush-Larsen step") {
    const auto rl = base->with_rush_larsen_step(0.01);
    CHECK(rl->rows() != base_rl->rows());
    CHECK(rl->rush_larsen_step_ms() == 0.01);
    CHECK(base->with_rush_larsen_step(0.02)->rows() == base_rl->rows());  // and the same one hits
  }
  SUBCASE("another plugin file or scalar evaluation") {
    Population other = pop;
    other.model_origin += "x";
    CHECK(fibrodem::VoltageTable::build(other)->rows() != base->rows());
    Population scalar = pop;
    scalar.scalar_reference = true;
    CHECK(fibrodem::VoltageTable::build(scalar)->rows() != base->rows());
  }
  SUBCASE("the same inputs hit") {
    const long long hits = cache.hits();
    CHECK(fibrodem::VoltageTable::build(colman_cell())->rows() == base->rows());
    CHECK(cache.hits() == hits + 1);
  }
}

TEST_CASE("table cache: stays within its budget over many parameter sets") {
  auto& cache = VoltageTableCache::instance();
  cache.clear();
  Population pop = colman_cell();
  std::size_t largest = 0;
  const int sets = 24;  // colman: ~0.7 MB of a, b plus ~1.4 MB with RL columns per set, ~50 MB in all
  for (int i = 0; i < sets; ++i) {
    pop.params[0] *= 1.01;
    const auto table = fibrodem::VoltageTable::build(pop);
    REQUIRE(table->with_rush_larsen_step(0.02) != nullptr);
    CHECK(cache.bytes() <= VoltageTableCache::kBudgetBytes);
    largest = std::max(largest, cache.bytes());
  }
  MESSAGE("largest cache size " << largest << " bytes in " << cache.entries() << " entries");
  CHECK(cache.entries() < static_cast<std::size_t>(2 * sets));  // some were evicted
  CHECK(cache.entries() >= 2);
  CHECK(largest > VoltageTableCache::kBudgetBytes / 2);  // and it was filled, not emptied
}

TEST_CASE("table cache: each table counts its own clamps") {
  VoltageTableCache::instance().clear();
  Population a = colman_cell(), b = colman_cell();
  REQUIRE(a.use_lookup_table());
  REQUIRE(b.use_lookup_table());
  REQUIRE(a.table->rows() == b.table->rows());
  a.state(a.voltage_state, 0) = -500;  // off the table
  a.evaluate(0.0);
  b.evaluate(0.0);
  CHECK(a.table->clamp_count() == 1);
  CHECK(b.table->clamp_count() == 0);
}

TEST_CASE("table cache: threads building the same table share one copy" * doctest::test_suite("threads")) {
  VoltageTableCache::instance().clear();
  const Population pop = colman_cell();
  std::vector<std::shared_ptr<fibrodem::VoltageTable>> tables(4);
  std::vector<std::thread> threads;
  for (auto& t : tables) threads.emplace_back([&pop, &t] { t = fibrodem::VoltageTable::build(pop); });
  for (auto& t : threads) t.join();
  // A thread that sampled the rows while another stored them gets the stored
  // copy back from insert(); later look-ups find that copy too.
  const auto stored = fibrodem::VoltageTable::build(pop)->rows();
  for (const auto& t : tables) CHECK(t->rows() == stored);
  CHECK(VoltageTableCache::instance().entries() == 1);
}
