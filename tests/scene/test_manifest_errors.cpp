// Every bad manifest is refused with a message that names the JSON path of the
// offending value and what was expected; nothing crashes.
#include <doctest/doctest.h>

#include <cstdio>
#include <functional>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// Sets up (parses, builds, loads plugins) without running, as `validate` does.
void set_up(const json& manifest) { Simulation sim(parse_scene(manifest)); }

std::string error_of(const json& manifest, std::string* path = nullptr) {
  try {
    set_up(manifest);
  } catch (const ManifestError& e) {
    if (path) *path = e.path();
    return e.what();
  }
  return "(no error)";
}

void expect_error(std::function<void(json&)> edit, const std::string& path, const std::string& fragment) {
  json m = testing::passive_cell_manifest();
  edit(m);
  std::string got_path;
  const std::string message = error_of(m, &got_path);
  CAPTURE(message);
  CHECK(got_path == path);
  CHECK(message.find(path) != std::string::npos);
  CHECK(message.find(fragment) != std::string::npos);
}

}  // namespace

TEST_CASE("the starting manifest is valid") { CHECK_NOTHROW(set_up(testing::passive_cell_manifest())); }

TEST_CASE("unknown keys are named, at any depth") {
  expect_error([](json& m) { m["durration_ms"] = 5; }, "durration_ms", "unknown key");
  expect_error([](json& m) { m["stimulus"][0]["amplitude"] = 5; }, "stimulus[0].amplitude", "unknown key");
  expect_error([](json& m) { m["solver"]["tolerance"] = 1; }, "solver.tolerance", "unknown key");
  expect_error([](json& m) { m["tissue"]["cells"] = 3; }, "tissue.cells", "unknown key");
}

TEST_CASE("wrong types and out-of-range numbers say what was expected") {
  expect_error([](json& m) { m["duration_ms"] = "long"; }, "duration_ms", "expected a number");
  expect_error([](json& m) { m["solver"]["dt_ms"] = -1; }, "solver.dt_ms", "expected a number in [");
  expect_error([](json& m) { m["solver"]["method"] = "rk4"; }, "solver.method", "\"cvode\"");
  expect_error([](json& m) { m["fibrodem"] = 2; }, "fibrodem", "expected an integer in [1, 1]");
  expect_error([](json& m) { m.erase("duration_ms"); }, "duration_ms", "required value is missing");
  expect_error([](json& m) { m["tissue"] = {{"builder", "strand"}, {"cells", 0}}; }, "tissue.cells", "in [1,");
  expect_error([](json& m) { m["coupling"] = {{"D_f_nS", -2}}; }, "coupling.D_f_nS", "expected a number in [0");
  expect_error([](json& m) { m["effects"] = {"electrophysiology", "telepathy"}; }, "effects[1]", "unknown effect");
}

TEST_CASE("the RMP and CV measurement options are checked") {
  expect_error([](json& m) { m["output"]["biomarkers"] = {{"rmp", "window"}}; }, "output.biomarkers.rmp",
               "expected one of \"onset\", \"pre_upstroke\"");
  expect_error([](json& m) { m["output"]["biomarkers"] = {{"rmp_window_ms", 3}}; }, "output.biomarkers.rmp_window_ms",
               "applies only with \"rmp\": \"pre_upstroke\"");
  expect_error([](json& m) { m["output"]["biomarkers"] = {{"rmp", "pre_upstroke"}, {"rmp_window_ms", 0}}; },
               "output.biomarkers.rmp_window_ms", "expected a number in [");
  expect_error([](json& m) { m["output"]["biomarkers"] = {{"rmp", "pre_upstroke"}, {"rmp_gap_ms", -1}}; },
               "output.biomarkers.rmp_gap_ms", "expected a number in [");
  expect_error([](json& m) { m["output"]["biomarkers"] = {{"cv", "slope"}}; }, "output.biomarkers.cv",
               "expected one of \"fit\", \"transit\"");
  json ok = testing::passive_cell_manifest();
  ok["output"]["biomarkers"] = {{"rmp", "pre_upstroke"}, {"rmp_window_ms", 3}, {"rmp_gap_ms", 1}, {"cv", "transit"}};
  CHECK_NOTHROW(set_up(ok));
}

TEST_CASE("unknown builder, model, variant and parameter are named with what exists") {
  expect_error([](json& m) { m["tissue"]["builder"] = "sphere"; }, "tissue.builder", "\"strand\"");
  expect_error([](json& m) { m["cells"]["fibroblast"]["model"] = "nope"; }, "cells.fibroblast.model",
               "models found:");
  expect_error([](json& m) { m["cells"]["fibroblast"]["model"] = "nope"; }, "cells.fibroblast.model",
               "passive_fibroblast");
  expect_error([](json& m) { m["cells"]["fibroblast"]["variant"] = "v2"; }, "cells.fibroblast.variant",
               "has no variant");
  expect_error([](json& m) { m["cells"]["fibroblast"]["parameters"] = {{"g_bogus", 1.0}}; },
               "cells.fibroblast.parameters.g_bogus", "R_GOhm");
  expect_error([](json& m) { m["cells"]["fibroblast"]["parameters"] = {{"C_pF", 0.0}}; },
               "cells.fibroblast.parameters.C_pF", "capacitance > 0");
  expect_error([](json& m) { m["cells"]["wizard"] = {{"model", "x"}}; }, "cells.wizard", "unknown cell type");
}

TEST_CASE("a cell type in the tissue needs a model") {
  expect_error([](json& m) { m["tissue"] = {{"builder", "cell_pair"}, {"fibroblasts", 2}}; }, "cells.myocyte",
               "no cell model");
}

TEST_CASE("a stimulus target that names no cell is refused") {
  expect_error([](json& m) { m["stimulus"][0]["target"] = "myocyte"; }, "stimulus[0].target", "no myocyte");
  expect_error([](json& m) { m["stimulus"][0]["target"] = {3}; }, "stimulus[0].target[0]", "does not exist");
  expect_error([](json& m) {
    m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", 10}};
    m["stimulus"][0]["target"] = {{"y_min_frac", 0.95}, {"type", "myocyte"}};
  }, "stimulus[0].target", "no cell");
  expect_error([](json& m) { m["stimulus"][0]["target"] = 7; }, "stimulus[0].target", "expected a cell type");
}

TEST_CASE("a region in mm that holds no cell, or has no size, is refused at its JSON path") {
  // The single cell sits at the origin: a rectangle or circle away from it holds no cell.
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"x_min_mm", 1}, {"x_max_mm", 2}, {"y_min_mm", 0}, {"y_max_mm", 1}};
  }, "stimulus[0].target", "no cell");
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"center_x_mm", 5}, {"center_y_mm", 5}, {"radius_mm", 1}};
  }, "stimulus[0].target", "no cell");
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"center_x_mm", 0}, {"center_y_mm", 0}, {"radius_mm", -0.5}};
  }, "stimulus[0].target.radius_mm", "expected a number in [");
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"center_x_mm", 0}, {"center_y_mm", 0}};
  }, "stimulus[0].target.radius_mm", "required value is missing");
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"x_min_mm", 1}, {"x_max_mm", 0}, {"y_min_mm", 0}, {"y_max_mm", 1}};
  }, "stimulus[0].target.x_max_mm", "expected x_max_mm >= x_min_mm");
  expect_error([](json& m) {
    m["stimulus"][0]["target"] = {{"x_min_frac", 0}, {"radius_mm", 1}};
  }, "stimulus[0].target", "one form of region");
}

TEST_CASE("output.reentry's delay is a whole number of samples") {
  expect_error([](json& m) { m["output"]["reentry"] = {{"every_ms", 2}, {"tau_ms", 5}}; }, "output.reentry.tau_ms",
               "whole multiple of every_ms");
  expect_error([](json& m) { m["output"]["reentry"] = {{"f_min_hz", 10}, {"f_max_hz", 5}}; },
               "output.reentry.f_max_hz", "more than f_min_hz");
  expect_error([](json& m) { m["output"]["reentry"] = {{"clinical_f_min_hz", 12}, {"clinical_f_max_hz", 3}}; },
               "output.reentry.clinical_f_max_hz", "more than clinical_f_min_hz");
  expect_error([](json& m) { m["output"]["reentry"] = {{"ps_density_bin_mm", 0}}; },
               "output.reentry.ps_density_bin_mm", "");
}

TEST_CASE("traces name existing cells and variables") {
  expect_error([](json& m) { m["output"]["traces"]["cells"] = {0, 4}; }, "output.traces.cells[1]",
               "does not exist");
  expect_error([](json& m) { m["output"]["traces"]["variables"] = {"V", "Ca_i"}; }, "output.traces.variables[1]",
               "neither a state nor an output");
  expect_error([](json& m) { m["output"]["traces"]["every_ms"] = 0.015; }, "output.traces.every_ms",
               "multiple of solver.dt_ms");
}

TEST_CASE("a missing or malformed manifest file is a ManifestError") {
  CHECK_THROWS_AS(read_manifest_file("/nonexistent/manifest.json"), ManifestError);
  const auto dir = testing::scratch_dir("bad_json");
  std::ofstream(dir / "bad.json") << "{ \"fibrodem\": 1, ";
  CHECK_THROWS_WITH_AS(read_manifest_file((dir / "bad.json").string()),
                       doctest::Contains("not valid JSON"), ManifestError);
}

TEST_CASE("--set overrides any value by its dotted path") {
  json m = testing::passive_cell_manifest();
  apply_override(m, "solver.dt_ms=0.02");
  apply_override(m, "stimulus[0].amplitude_pA=3.5");
  apply_override(m, "cells.fibroblast.parameters.R_GOhm=5");
  apply_override(m, "name=renamed");
  CHECK(m["solver"]["dt_ms"] == 0.02);
  CHECK(m["stimulus"][0]["amplitude_pA"] == 3.5);
  CHECK(m["cells"]["fibroblast"]["parameters"]["R_GOhm"] == 5);
  CHECK(m["name"] == "renamed");
  CHECK_THROWS_AS(apply_override(m, "stimulus[4].amplitude_pA=1"), ManifestError);
  // An index longer than any number (found by the fuzzer: std::stoul threw out_of_range).
  CHECK_THROWS_WITH_AS(apply_override(m, "stimulus[0333333333333333333333333].amplitude_pA=1"),
                       doctest::Contains("stimulus[0333333333333333333333333]: --set"), ManifestError);
  CHECK_THROWS_AS(apply_override(m, "no_equals_sign"), ManifestError);
  CHECK_THROWS_AS(apply_override(m, "name.inner=1"), ManifestError);
}

TEST_CASE("the command line exits non-zero and names the path") {
  const auto dir = testing::scratch_dir("cli_errors");
  json m = testing::passive_cell_manifest();
  m["solver"]["dt_ms"] = "small";
  std::ofstream(dir / "bad.json") << m.dump();
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem validate " +
                              (dir / "bad.json").string() + " 2>&1";
  const testing::CommandOutput result = testing::run_command(command);
  CAPTURE(result.output);
  CHECK(result.status == 2);
  CHECK(result.output.find("solver.dt_ms") != std::string::npos);
  CHECK(result.output.find("expected a number") != std::string::npos);
}

TEST_CASE("invalid UTF-8 in a manifest's strings is a ManifestError, not a JSON exception (found by fuzzing)") {
  json m = testing::passive_cell_manifest();
  // A list of effects whose first string is not UTF-8: the error shows it.
  m["effects"] = json::array({std::string("\xde\x9a\x93\xa2") + "ctrophysiology", "coupling"});
  CHECK_THROWS_AS(parse_scene(m), ManifestError);
  CHECK_NOTHROW(describe_json(m["effects"]));
}

TEST_CASE("cells.TYPE.initial_state overrides a model's initial values by state name, checked against each state's range") {
  json m = testing::passive_cell_manifest();
  m["stimulus"] = json::array();
  m["cells"]["fibroblast"]["initial_state"] = {{"V", -65.0}};
  {
    Simulation sim(parse_scene(m));
    sim.run();
    CHECK(sim.trace("V", 0).front() == -65.0);  // the first sample, at t = 0
  }
  m["cells"]["fibroblast"]["initial_state"] = {{"Vx", -65.0}};
  CHECK_THROWS_WITH_AS(set_up(m), doctest::Contains("cells.fibroblast.initial_state.Vx: model passive_fibroblast has no state \"Vx\""),
                       ManifestError);
  m["cells"]["fibroblast"]["initial_state"] = {{"V", "low"}};
  CHECK_THROWS_WITH_AS(set_up(m), doctest::Contains("cells.fibroblast.initial_state.V: expected a number"), ManifestError);
  // A gate outside [0, 1].
  json colman = json::parse(R"({"fibrodem": 1, "name": "c", "duration_ms": 1,
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {"myocyte": {"model": "colman", "initial_state": {"m": 1.5}}}})");
  CHECK_THROWS_WITH_AS(set_up(colman), doctest::Contains("cells.myocyte.initial_state.m: expected a value within the state's range [0, 1]"),
                       ManifestError);
}
