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
