// `fibrodem check-plugin`: every bundled model passes every check, and each
// deliberately broken test model (tests/plugins/) fails the check that its
// fault breaks, with a message naming the state.
#include <doctest/doctest.h>

#include <cstdlib>
#include <sys/wait.h>

#include "model/plugin_check.hpp"
#include "model/plugin_registry.hpp"

using namespace fibrodem;

namespace {
const std::filesystem::path kPlugins = std::filesystem::path(FIBRODEM_BINARY_DIR) / "plugins";
const std::filesystem::path kTestPlugins = std::filesystem::path(FIBRODEM_BINARY_DIR) / "test_plugins";

PluginCheckReport check_test_plugin(const std::string& name) {
  return check_plugin(*open_cell_model_file(kTestPlugins / ("libfibrodem_" + name + ".so")));
}

const PluginCheck& find_check(const PluginCheckReport& report, const std::string& name) {
  for (const auto& check : report.checks)
    if (check.name == name) return check;
  FAIL("no check named " << name);
  return report.checks.front();
}

std::string all_faults(const PluginCheck& check) {
  std::string s;
  for (const auto& f : check.faults) s += f + "\n";
  return s;
}

// The checks a report failed, by name.
std::vector<std::string> failed(const PluginCheckReport& report) {
  std::vector<std::string> names;
  for (const auto& check : report.checks)
    if (!check.passed()) names.push_back(check.name);
  return names;
}

int exit_code(const std::string& command) {
  const int status = std::system((command + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST_CASE("check-plugin: every bundled model passes every check") {
  PluginRegistry registry({kPlugins});
  const auto names = registry.available();
  REQUIRE(names.size() >= 5);  // colman, courtemanche, maleckar_active2, passive_fibroblast, rice
  for (const auto& name : names) {
    CAPTURE(name);
    const PluginCheckReport report = check_plugin(*registry.load(name));
    for (const auto& check : report.checks) {
      CAPTURE(check.name);
      CHECK_MESSAGE(check.passed(), all_faults(check));
    }
    // Every check that applies to every model ran.
    CHECK(find_check(report, "derivatives written").skipped.empty());
    CHECK(find_check(report, "bounds respected over a paced beat").skipped.empty());
  }
}

TEST_CASE("check-plugin: the paced beat of the check fires a colman cell") {
  // The beat check is only worth something if the cell depolarises: colman's
  // rest is -75.1 mV (docs/topics/models.md#colman) and a 20 pA/pF pulse for 2 ms fires it.
  PluginRegistry registry({kPlugins});
  const auto report = check_plugin(*registry.load("colman"));
  const std::string note = find_check(report, "bounds respected over a paced beat").note;
  CAPTURE(note);
  CHECK(note.find("variant 'colman2013': V from -75.") != std::string::npos);
  const double peak = std::stod(note.substr(note.find(" to ") + 4));
  CHECK(peak > 0);  // an overshoot
}

TEST_CASE("check-plugin: the well-behaved test model passes, each broken one fails with its fault named") {
  CHECK(check_test_plugin("well_behaved").passed());

  {  // a gate never written in evaluate() would stay frozen
    const auto report = check_test_plugin("frozen_gate");
    const auto& written = find_check(report, "derivatives written");
    // In every probed cell (kProbeCells: 11 with AVX2, 19 with AVX-512).
    const std::string cells = std::to_string(kProbeCells);
    CHECK(all_faults(written).find("state 'n' (#1): a and b not written by evaluate() in " + cells + " of " + cells +
                                   " cells (SIMD lanes)") != std::string::npos);
    CHECK(all_faults(written).find("(scalar path)") != std::string::npos);
    CHECK(find_check(report, "metadata").passed());
  }
  {  // an initial value outside its own bounds
    const auto report = check_test_plugin("initial_out_of_bounds");
    CHECK(all_faults(find_check(report, "metadata")).find("state 'n' starts at 1.500000, outside its bounds") !=
          std::string::npos);
  }
  {  // a voltage_only gate whose rate depends on Ca_i
    const auto report = check_test_plugin("voltage_only_on_ca");
    CHECK(failed(report) == std::vector<std::string>{"voltage_only gates depend on V alone"});
    CHECK(all_faults(find_check(report, "voltage_only gates depend on V alone"))
              .find("gate 'n' is marked voltage_only, but its a changes") != std::string::npos);
    CHECK(all_faults(find_check(report, "voltage_only gates depend on V alone")).find("when state 'Ca_i' moves") !=
          std::string::npos);
  }
  {  // two states of one name
    const auto report = check_test_plugin("duplicate_states");
    CHECK(all_faults(find_check(report, "metadata")).find("two states are named 'V'") != std::string::npos);
  }
}

TEST_CASE("check-plugin: the metadata check lists every fault, variants included") {
  ModelInfo info;
  info.name = "m";
  info.states = {{"V", "mV", -50.0, -200.0, 200.0, false}, {"x", "1", 2.0, 0.0, 1.0, true}};
  info.parameters = {{"C_pF", "pF", 10.0, ""}};
  info.variants = {{"v1", "", {{"g_missing", 1.0}}, {}}, {"v2", "", {{"C_pF", -1.0}}, {{"x", 3.0}, {"nope", 0.0}}}};
  info.voltage_state = 0;
  info.capacitance_parameter = 0;
  const auto problems = model_info_problems(info);
  auto has = [&](const std::string& text) {
    for (const auto& p : problems)
      if (p.find(text) != std::string::npos) return true;
    return false;
  };
  CAPTURE(problems.size());
  CHECK(problems.size() == 5);
  CHECK(has("state 'x' starts at 2.000000, outside its bounds"));
  CHECK(has("variant 'v1' sets parameter 'g_missing', which the model does not have"));
  CHECK(has("variant 'v2' sets the capacitance 'C_pF' to -1.000000, expected > 0 pF"));
  CHECK(has("variant 'v2' starts state 'x' at 3.000000, outside its bounds"));
  CHECK(has("variant 'v2' sets the initial value of state 'nope', which the model does not have"));
  // The loader refuses such a model at load, whether or not a variant is selected.
  CHECK_THROWS_WITH(check_model_info(info, "libfibrodem_m.so"), doctest::Contains("(and 4 more: fibrodem check-plugin lists them)"));
}

TEST_CASE("check-plugin: a plugin built against another C++ standard-library ABI is refused, naming both") {
  // Built with -D_GLIBCXX_USE_CXX11_ABI=0 (tests/CMakeLists.txt): its
  // std::string in ModelInfo would be read as garbage.
  CHECK_THROWS_WITH_AS(open_cell_model_file(kTestPlugins / "libfibrodem_old_stdlib_abi.so"),
                       doctest::Contains("libstdc++ (_GLIBCXX_USE_CXX11_ABI=0) but this fibrodem uses libstdc++ "
                                         "(_GLIBCXX_USE_CXX11_ABI=1)"),
                       PluginError);
}

TEST_CASE("check-plugin on the command line: exit 0 when every check passes, 3 when one fails") {
  const std::string fibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem check-plugin ";
  CHECK(exit_code(fibrodem + "passive_fibroblast") == 0);
  CHECK(exit_code(fibrodem + (kTestPlugins / "libfibrodem_well_behaved.so").string()) == 0);
  CHECK(exit_code(fibrodem + (kTestPlugins / "libfibrodem_frozen_gate.so").string()) == 3);
  CHECK(exit_code(fibrodem + (kTestPlugins / "libfibrodem_old_stdlib_abi.so").string()) == 3);
  CHECK(exit_code(fibrodem + "no_such_model") == 3);
}
