// The one options path of the S1-S2 studies (`fibrodem restitution`,
// `fibrodem vulnerable-window` and the Python module's restitution() and
// vulnerable_window()): what both front ends give (a manifest, overrides,
// an output folder and the study's options struct, whose members hold the
// defaults) becomes the engine's options here, and each numeric option's
// limits are declared once, below. The command line checks its flags with
// them as it parses (apps/study_flags.cpp); prepare_*() checks every value
// with them again, so that a caller that is not the command line (Python)
// meets the same limits.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "study/restitution.hpp"
#include "study/vulnerable_window.hpp"

namespace fibrodem {

// A numeric option of a study: its two names and its limits.
struct StudyNumberOption {
  const char* flag;     // the command line's, e.g. "--capture-fraction"
  const char* keyword;  // the Python module's, e.g. "capture_fraction"
  double min = 0;
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool whole = false;  // a whole number (a count or an index)

  // "" when `value` is within the limits, else what was expected ("a number
  // in [0, 1]", "a number > 0", ...).
  std::string violation(double value) const;
  // ManifestError naming the option by both names when `value` is outside.
  void check(double value) const;
};

namespace study_option {
inline constexpr StudyNumberOption capture_fraction{"--capture-fraction", "capture_fraction", 0, 1};
inline constexpr StudyNumberOption seeds{"--seeds", "seeds", 1, 10000, false, true};
// restitution
inline constexpr StudyNumberOption intervals{"--intervals", "intervals_ms", 0, std::numeric_limits<double>::infinity(), true};
inline constexpr StudyNumberOption cells{"--cells", "cells", 0, std::numeric_limits<double>::infinity(), false, true};
inline constexpr StudyNumberOption erp_resolution{"--resolution", "resolution_ms"};
// vulnerable-window
inline constexpr StudyNumberOption scan_from{"--from", "from_ms", 0, std::numeric_limits<double>::infinity(), true};
inline constexpr StudyNumberOption scan_to{"--to", "to_ms", 0, std::numeric_limits<double>::infinity(), true};
inline constexpr StudyNumberOption scan_step{"--step", "step_ms", 0, std::numeric_limits<double>::infinity(), true};
inline constexpr StudyNumberOption bisection_resolution{"--resolution", "resolution_ms", 0,
                                                        std::numeric_limits<double>::infinity(), true};
}  // namespace study_option

// What a study is given besides its options: the manifest (as read), the
// overrides (PATH=VALUE, applied in order) and the output folder (empty:
// the study's default, out/<study>_<name>).
struct StudyInput {
  json manifest;
  std::vector<std::string> overrides;
  std::string out;
};

// Applies the overrides to input.manifest, checks the options against their
// limits (ManifestError naming the option) and sets options.out.
RestitutionOptions prepare_restitution(StudyInput& input, RestitutionOptions options);

// As prepare_restitution; the scan is given whole (from, to and step > 0,
// from <= to) or not at all (all three 0: default_scan).
VulnerableWindowOptions prepare_vulnerable_window(StudyInput& input, VulnerableWindowOptions options);

}  // namespace fibrodem
