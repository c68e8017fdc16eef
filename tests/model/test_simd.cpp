// Cell models in SIMD lanes (sdk/model/simd.hpp, block_access.hpp):
//  (a) lanes and the scalar reference path (solver.simd false) differ by
//      round-off only, over whole beats of every ionic model;
//  (b) a cell's derivatives do not depend on where it sits in its block (a
//      last lane group narrower than the register included).
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "model/simd.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// A strand of 12 cells of one model, one beat, V traced on three cells (a
// myocyte strand conducts; fibroblasts are all driven, as they do not).
json strand(const std::string& model, const std::string& type, bool simd) {
  const bool myocyte = type == "myocyte";
  json m = {{"fibrodem", 1},
            {"name", "simd_" + model},
            {"duration_ms", myocyte ? 400.0 : 200.0},
            {"tissue", {{"builder", "strand"}, {"type", type}, {"cells", 12}}},
            {"cells", {{type, {{"model", model}}}}},
            {"coupling", {{"D_m_nS", 1000}, {"D_f_nS", 2}}},
            {"stimulus", {{{"target", myocyte ? json{0, 1} : json(type)}, {"start_ms", 10},
                           {"duration_ms", myocyte ? 2 : 20}, {"amplitude_pA", myocyte ? 4000 : 40}}}},
            {"solver", {{"method", "rush_larsen"}, {"dt_ms", 0.01}, {"simd", simd}}},
            {"output", {{"traces", {{"cells", {0, 6, 11}}, {"variables", {"V"}}, {"every_ms", 0.5}}}}}};
  return m;
}

}  // namespace

TEST_CASE("SIMD lanes and the scalar reference path agree to round-off" * doctest::test_suite("slow")) {
  // Measured (this build, AVX-512): V RMS ~5e-14 mV and APD90 ~3e-13 ms on
  // the colman strand; xsimd's exp/log are within ~1 ulp of glibc's, and the
  // difference stays at round-off through a beat. 1e-9 leaves room for other
  // CPUs and compilers while any real difference (a wrong select, a lane mixed
  // up) moves V by millivolts.
  const std::vector<std::pair<std::string, std::string>> models = {
      {"colman", "myocyte"}, {"courtemanche", "myocyte"}, {"maleckar_active2", "fibroblast"},
      {"passive_fibroblast", "fibroblast"}};
  for (const auto& [model, type] : models) {
    const std::string model_name = model;  // (clang 14 cannot capture a structured binding)
    CAPTURE(model_name);
    Simulation lanes(parse_scene(strand(model, type, true)));
    Simulation scalar(parse_scene(strand(model, type, false)));
    lanes.run();
    scalar.run();
    for (int cell : {0, 6, 11}) {
      const auto& a = lanes.trace("V", cell);
      const auto& b = scalar.trace("V", cell);
      REQUIRE(a.size() == b.size());
      double sum2 = 0, swing = 0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        sum2 += (a[i] - b[i]) * (a[i] - b[i]);
        swing = std::max(swing, std::abs(a[i] - a[0]));
      }
      CHECK(swing > 5.0);  // the cells really were excited
      CHECK(std::sqrt(sum2 / static_cast<double>(a.size())) < 1e-9);
    }
    const auto& ba = lanes.biomarkers();
    const auto& bb = scalar.biomarkers();
    REQUIRE(ba.size() == bb.size());
    for (std::size_t i = 0; i < ba.size(); ++i) {
      if (!std::isfinite(ba[i].apd90_ms)) continue;
      CHECK(std::abs(ba[i].apd90_ms - bb[i].apd90_ms) < 1e-9);
    }
  }
}

TEST_CASE("a cell's derivatives do not depend on its place in the block") {
  // 2 kLanes + 3 identical cells: two full lane groups and a narrower last one.
  PluginRegistry registry;
  for (const char* name : {"colman", "courtemanche", "maleckar_active2"}) {
    CAPTURE(name);
    Population pop;
    pop.model = registry.load(name);
    for (const auto& p : pop.info().parameters) pop.params.push_back(p.default_value);
    for (const auto& s : pop.info().states) pop.initial_state.push_back(s.initial);
    pop.voltage_state = pop.info().voltage_state;
    const std::size_t n = 2 * simd::kLanes + 3;
    pop.cells.resize(n);
    pop.reset();
    for (std::size_t c = 0; c < n; ++c) pop.state(pop.voltage_state, c) = -20.0;  // mid-upstroke rates
    pop.evaluate(0.0);
    for (std::size_t k = 0; k < pop.n_states(); ++k)
      for (std::size_t c = 1; c < n; ++c) {
        CHECK(pop.a[k * n + c] == pop.a[k * n]);
        CHECK(pop.b[k * n + c] == pop.b[k * n]);
      }
  }
}
