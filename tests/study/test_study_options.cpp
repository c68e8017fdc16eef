// The one options path of the S1-S2 studies (study/study_options.hpp): what
// the command line and the Python module both call to turn a manifest,
// overrides and options into the engine's options, with each option's limits.
#include <doctest/doctest.h>

#include "study/study_options.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_CASE("a study option's limits: open and closed ends, whole numbers") {
  CHECK(study_option::capture_fraction.violation(0) == "");
  CHECK(study_option::capture_fraction.violation(1) == "");
  CHECK(study_option::capture_fraction.violation(1.5) == "a number in [0, 1]");
  CHECK(study_option::scan_step.violation(0) == "a number > 0");
  CHECK(study_option::erp_resolution.violation(0) == "");
  CHECK(study_option::erp_resolution.violation(-0.5) == "a number >= 0");
  CHECK(study_option::cells.violation(3) == "");
  CHECK(study_option::cells.violation(-1) == "a whole number >= 0");
  CHECK(study_option::seeds.violation(10001) == "a whole number in [1, 10000]");
  CHECK_THROWS_WITH_AS(study_option::capture_fraction.check(-0.25),
                       "manifest: --capture-fraction (capture_fraction): expected a number in [0, 1], got -0.25",
                       ManifestError);
}

TEST_CASE("prepare_restitution applies the overrides, checks the options and names the default folder") {
  StudyInput input{testing::passive_cell_manifest(), {"name=cell_b", "duration_ms=300"}, ""};
  RestitutionOptions given;
  given.intervals_ms = {400, 250};
  const RestitutionOptions options = prepare_restitution(input, given);
  CHECK(input.manifest["duration_ms"] == 300);
  CHECK(options.out == std::filesystem::path("out/restitution_cell_b"));
  CHECK(options.intervals_ms == std::vector<double>{400, 250});
  // The defaults are the options struct's own (the command line's --help
  // and the Python keywords show them).
  CHECK(options.capture_fraction == 0.5);
  CHECK(options.erp_resolution_ms == 1);

  input.out = "elsewhere";
  CHECK(prepare_restitution(input, given).out == std::filesystem::path("elsewhere"));
  given.intervals_ms = {400, -1};
  CHECK_THROWS_WITH_AS(prepare_restitution(input, given),
                       "manifest: --intervals (intervals_ms): expected a number > 0, got -1", ManifestError);
}

TEST_CASE("prepare_vulnerable_window takes a scan whole or not at all") {
  StudyInput input{testing::passive_cell_manifest(), {}, ""};
  VulnerableWindowOptions given;
  const auto name = input.manifest.value("name", std::string());
  CHECK(prepare_vulnerable_window(input, given).out == std::filesystem::path("out/vulnerable_window_" + name));
  given.scan = {60, 80, 10, 1};
  CHECK(prepare_vulnerable_window(input, given).scan.step_ms == 10);
  given.scan = {60, 0, 0, 1};
  CHECK_THROWS_WITH_AS(
      prepare_vulnerable_window(input, given),
      "manifest: --from/--to/--step: give all three, with 0 < from <= to and step > 0 (got from 60, to 0, step 0)",
      ManifestError);
  given.scan = {60, 80, 10, 0};
  CHECK_THROWS_AS(prepare_vulnerable_window(input, given), ManifestError);
  given.scan = {};
  given.seeds = 20000;
  CHECK_THROWS_WITH_AS(prepare_vulnerable_window(input, given),
                       "manifest: --seeds (seeds): expected a whole number in [1, 10000], got 20000", ManifestError);
}
