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

// The error a run of manifest m stops with, the broken test plugins first on
// the search path ("" if it does not stop).
std::string run_error(const json& m) {
  auto registry = std::make_shared<PluginRegistry>(std::vector<std::filesystem::path>{kBadPlugins, kPlugins});
  Simulation sim(parse_scene(m), registry);
  try {
    sim.run();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
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

TEST_CASE("a model whose rate turns NaN at a step far below the stability limit is blamed, not the step") {
  const auto dir = testing::scratch_dir("nan_model");
  json m = testing::passive_cell_manifest();
  m["cells"]["fibroblast"] = {{"model", "misbehaves"}, {"parameters", {{"fault", 3}}}};
  m["duration_ms"] = 20;
  m["solver"] = {{"method", "rush_larsen"}, {"dt_ms", 0.01}};  // one uncoupled cell: no explicit limit at all
  m["output"]["dir"] = dir.string();
  const std::string message = run_error(m);
  CAPTURE(message);
  CHECK(message.find("state 'V' = nan") != std::string::npos);
  CHECK(message.find("so the model is the likely cause, not the step: model misbehaves (") != std::string::npos);
  CHECK(message.find("libfibrodem_misbehaves.so") != std::string::npos);
  CHECK(message.find("The cell's states after that step (each finite one is its last finite value") != std::string::npos);
  CHECK(message.find("fibrodem check-plugin misbehaves") != std::string::npos);
  CHECK(message.find("try a smaller solver.dt_ms") == std::string::npos);
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  CHECK(summary["status"] == "failed");
}

TEST_CASE("summary.json records every parameter value used, run.log warns of variant overrides and shadowed plugins") {
  const auto dir = testing::scratch_dir("parameters_used");
  // A copy of a bundled plugin earlier on the search path hides the bundled one.
  const auto shadow = testing::scratch_dir("shadowing_plugins");
  std::filesystem::copy_file(kPlugins / "libfibrodem_maleckar_active2.so", shadow / "libfibrodem_maleckar_active2.so");
  json m = testing::passive_cell_manifest();
  // Variant "depolarised" sets its own values; the manifest replaces one of them.
  PluginRegistry probe({kPlugins});
  const ModelInfo& info = probe.load("maleckar_active2")->info();
  const VariantInfo* depolarised = nullptr;
  for (const auto& v : info.variants)
    if (v.name == "depolarised") depolarised = &v;
  REQUIRE(depolarised != nullptr);
  REQUIRE(!depolarised->parameters.empty());
  const auto& [name, variant_value] = *depolarised->parameters.begin();
  const double manifest_value = variant_value * 1.01 + 0.01;
  m["cells"]["fibroblast"] = {{"model", "maleckar_active2"}, {"variant", "depolarised"},
                              {"parameters", {{name, manifest_value}}}};
  m["duration_ms"] = 2;
  m["plugin_path"] = shadow.string();
  m["output"]["dir"] = dir.string();
  Simulation(parse_scene(m)).run();
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  const json& used = summary["models"]["fibroblast"];
  CHECK(used["model"] == "maleckar_active2");
  CHECK(used["variant"] == "depolarised");
  CHECK(used["parameters"].size() == info.parameters.size());  // every parameter, not only those set
  CHECK(used["parameters"][name].get<double>() == manifest_value);
  for (const auto& [other, value] : depolarised->parameters)
    if (other != name) CHECK(used["parameters"][other].get<double>() == value);
  CHECK(summary["plugins"][0]["file"].get<std::string>().find("shadowing_plugins") != std::string::npos);
  const std::string log = testing::read_file(dir / "run.log");
  CHECK(log.find("cells.fibroblast.parameters." + name + " = ") != std::string::npos);
  CHECK(log.find("replaces variant depolarised's value") != std::string::npos);
  CHECK(log.find("hides " + (kPlugins / "libfibrodem_maleckar_active2.so").string()) != std::string::npos);
}

TEST_CASE("plugin_path must name existing directories") {
  json m = testing::passive_cell_manifest();
  m["plugin_path"] = json::array({"/no/such/plugin/dir"});
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("plugin_path[0]: expected an existing directory"),
                       ManifestError);
  m["plugin_path"] = 3;
  CHECK_THROWS_AS(parse_scene(m), ManifestError);
}

TEST_CASE("adaptive: a model whose rate turns NaN is named, with the cell's last finite states") {
  json m = testing::passive_cell_manifest();
  m["cells"]["fibroblast"] = {{"model", "misbehaves"}, {"parameters", {{"fault", 3}}}};
  m["duration_ms"] = 20;
  m["solver"] = {{"method", "adaptive"}};
  m["output"].erase("dir");
  const std::string message = run_error(m);
  CAPTURE(message);
  CHECK(message.find("model misbehaves computes it (check it with: fibrodem check-plugin misbehaves)") !=
        std::string::npos);
  // The step's start, restored: V finite there (the fault starts after 5 ms,
  // V then near its start of -50 mV plus 1 pA / 10 pF x 5 ms = -49.5 mV).
  const auto at = message.find("(its last finite values): V = ");
  REQUIRE(at != std::string::npos);
  const double V = std::stod(message.substr(at + std::string("(its last finite values): V = ").size()));
  CHECK(V == doctest::Approx(-49.5).epsilon(0.01));
}
