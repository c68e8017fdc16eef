// The plugin loader: finds models on its search path, refuses broken plugins
// with errors that name the file, and keeps a library loaded while any model
// made from it lives.
#include <doctest/doctest.h>

#include "model/plugin_registry.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
const std::filesystem::path kPlugins = std::filesystem::path(FIBRODEM_BINARY_DIR) / "plugins";
const std::filesystem::path kBadPlugins = std::filesystem::path(FIBRODEM_BINARY_DIR) / "test_plugins";
}  // namespace

TEST_CASE("the default search path finds the built plugins") {
  PluginRegistry registry;
  const auto names = registry.available();
  CHECK(std::find(names.begin(), names.end(), "passive_fibroblast") != names.end());
  auto model = registry.load("passive_fibroblast");
  CHECK(model->info().name == "passive_fibroblast");
  CHECK(model->info().states.size() == 1);
  CHECK(registry.load("passive_fibroblast") == model);  // loaded once
  const auto records = registry.loaded();
  REQUIRE(records.size() == 1);
  CHECK(records[0].sha256.size() == 64);
  CHECK(records[0].sha256 == sha256_of_file(records[0].file));
}

TEST_CASE("a model that is not found: the error lists the search path and the models found") {
  PluginRegistry registry({kPlugins, "/nonexistent/dir"});
  try {
    registry.load("does_not_exist");
    FAIL("expected a PluginError");
  } catch (const PluginError& e) {
    const std::string message = e.what();
    CHECK(message.find("does_not_exist") != std::string::npos);
    CHECK(message.find("/nonexistent/dir") != std::string::npos);
    CHECK(message.find("passive_fibroblast") != std::string::npos);
  }
}

TEST_CASE("an ABI mismatch and a missing entry point name the file") {
  PluginRegistry registry({kBadPlugins});
  CHECK_THROWS_WITH_AS(registry.load("bad_abi"), doctest::Contains("libfibrodem_bad_abi.so"), PluginError);
  CHECK_THROWS_WITH_AS(registry.load("bad_abi"), doctest::Contains("ABI"), PluginError);
  CHECK_THROWS_WITH_AS(registry.load("no_entry"), doctest::Contains("libfibrodem_no_entry.so"), PluginError);
  CHECK_THROWS_WITH_AS(registry.load("no_entry"), doctest::Contains("fibrodem_create_cell_model"), PluginError);
}

TEST_CASE("FIBRODEM_PLUGIN_PATH directories come first on the search path") {
  setenv("FIBRODEM_PLUGIN_PATH", "/first/dir:/second/dir", 1);
  const auto path = PluginRegistry::default_search_path();
  unsetenv("FIBRODEM_PLUGIN_PATH");
  REQUIRE(path.size() >= 3);
  CHECK(path[0] == "/first/dir");
  CHECK(path[1] == "/second/dir");
}

TEST_CASE("a model outlives the registry that loaded it (its library stays loaded)") {
  std::shared_ptr<const CellModel> model;
  {
    PluginRegistry registry({kPlugins});
    model = registry.load("passive_fibroblast");
  }
  // The registry is gone; calling into the library must still work.
  CHECK(model->info().name == "passive_fibroblast");
  std::vector<double> y = {-40.0}, params = {6.3, 10.7, -49.6}, in = {0.0}, a(1), b(1);
  BlockView v{0, 1, 1, y.data(), params.data(), in.data(), a.data(), b.data(), nullptr};
  model->evaluate(v, 0.0);
  // dV/dt = -(V - E)/(R C) = -(9.6)/(67.41) mV/ms
  CHECK(a[0] == doctest::Approx(-9.6 / (10.7 * 6.3)));
}

TEST_CASE("inconsistent metadata is refused at load, naming the plugin and the fault") {
  PluginRegistry registry({kBadPlugins});
  CHECK_THROWS_WITH_AS(registry.load("duplicate_states"), doctest::Contains("two states are named 'V'"), PluginError);
  CHECK_THROWS_WITH_AS(registry.load("duplicate_states"), doctest::Contains("libfibrodem_duplicate_states.so"),
                       PluginError);
  // Each rule on its own, without a plugin per case.
  auto info_with = [](auto change) {
    ModelInfo info;
    info.name = "m";
    info.states = {{"V", "mV", -50.0, -200.0, 200.0, false}};
    info.parameters = {{"C_pF", "pF", 10.0, ""}};
    info.voltage_state = 0;
    info.capacitance_parameter = 0;
    change(info);
    return info;
  };
  const std::filesystem::path file = "libfibrodem_m.so";
  CHECK_NOTHROW(check_model_info(info_with([](ModelInfo&) {}), file));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.states.clear(); }), file),
                    doctest::Contains("declares no states"));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.states[0].name = ""; }), file),
                    doctest::Contains("state 0 has no name"));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.states[0].lower = 300; }), file),
                    doctest::Contains("bounds reversed"));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.states[0].initial = 250; }), file),
                    doctest::Contains("outside its bounds"));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.parameters[0].default_value = 0; }), file),
                    doctest::Contains("expected > 0 pF"));
  CHECK_THROWS_WITH(check_model_info(info_with([](ModelInfo& i) { i.voltage_state = 3; }), file),
                    doctest::Contains("voltage_state 3"));
}

TEST_CASE("a model that throws from evaluate() stops the run naming it, outputs kept (fixed step, adaptive, CVODE)") {
  for (const char* method : {"euler", "adaptive", "cvode"}) {
    CAPTURE(method);
    const auto dir = testing::scratch_dir(std::string("throws_") + method);
    auto registry = std::make_shared<PluginRegistry>(std::vector<std::filesystem::path>{kBadPlugins, kPlugins});
    json m = testing::passive_cell_manifest();
    m["cells"]["fibroblast"] = {{"model", "misbehaves"}, {"parameters", {{"fault", 1}}}};
    m["duration_ms"] = 20;
    m["solver"] = {{"method", method}};
    if (std::string(method) == "euler") m["solver"]["dt_ms"] = 0.01;
    m["output"]["dir"] = dir.string();
    Simulation sim(parse_scene(m), registry);
    CHECK_THROWS_WITH(sim.run(), doctest::Contains("model misbehaves (fibroblast) threw from evaluate(): lookup out of range"));
    const json summary = json::parse(testing::read_file(dir / "summary.json"));
    CHECK(summary["status"] == "failed");
    // It stops at the first evaluation past 5 ms (CVODE tries far ahead at once).
    CHECK(summary["simulated_ms"].get<double>() <= 6);
    if (std::string(method) != "cvode")  // the samples before it are kept
      CHECK(testing::read_file(dir / "traces.csv").find("\n5,") != std::string::npos);
  }
}
