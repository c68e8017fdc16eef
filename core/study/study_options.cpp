#include "study/study_options.hpp"

#include <fmt/format.h>

#include <cmath>

#include "scene/scene.hpp"

namespace fibrodem {

std::string StudyNumberOption::violation(double value) const {
  const bool above_min = min_exclusive ? value > min : value >= min;
  if (above_min && value <= max && (!whole || std::floor(value) == value)) return "";
  const std::string kind = whole ? "a whole number" : "a number";
  if (std::isinf(max)) return fmt::format("{} {} {}", kind, min_exclusive ? ">" : ">=", min);
  return fmt::format("{} in {}{}, {}]", kind, min_exclusive ? "(" : "[", min, max);
}

void StudyNumberOption::check(double value) const {
  if (const std::string expected = violation(value); !expected.empty())
    throw ManifestError(fmt::format("{} ({})", flag, keyword), fmt::format("expected {}, got {}", expected, value));
}

namespace {

void apply_overrides(StudyInput& input) {
  for (const auto& o : input.overrides) apply_override(input.manifest, o);
}

}  // namespace

RestitutionOptions prepare_restitution(StudyInput& input, RestitutionOptions options) {
  apply_overrides(input);
  for (double ms : options.intervals_ms) study_option::intervals.check(ms);
  for (int cell : options.cells) study_option::cells.check(cell);
  study_option::erp_resolution.check(options.erp_resolution_ms);
  study_option::capture_fraction.check(options.capture_fraction);
  options.out = input.out.empty() ? default_restitution_dir(input.manifest) : std::filesystem::path(input.out);
  return options;
}

VulnerableWindowOptions prepare_vulnerable_window(StudyInput& input, VulnerableWindowOptions options) {
  apply_overrides(input);
  const WindowScan& scan = options.scan;
  if (scan.from_ms != 0 || scan.to_ms != 0 || scan.step_ms != 0) {
    if (!(scan.from_ms > 0 && scan.to_ms >= scan.from_ms && scan.step_ms > 0))
      throw ManifestError("--from/--to/--step",
                          fmt::format("give all three, with 0 < from <= to and step > 0 (got from {}, to {}, step {})",
                                      scan.from_ms, scan.to_ms, scan.step_ms));
  }
  study_option::bisection_resolution.check(scan.resolution_ms);
  study_option::capture_fraction.check(options.capture_fraction);
  if (options.seeds != 0) study_option::seeds.check(options.seeds);
  options.out = input.out.empty() ? default_vulnerable_window_dir(input.manifest) : std::filesystem::path(input.out);
  return options;
}

}  // namespace fibrodem
