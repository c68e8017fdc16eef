// CLI11's checks of the study options' limits, declared once in
// study/study_options.hpp: the validators the flags were written with, so
// that --help describes them as before ("POSITIVE", "FLOAT in [0 - 1]").
#include <CLI/CLI.hpp>
#include <cmath>
#include <stdexcept>

#include "apps/commands.hpp"

namespace fibrodem::cli {

CLI::Validator within_limits(const StudyNumberOption& option) {
  if (std::isinf(option.max) && option.min == 0)
    return option.min_exclusive ? CLI::PositiveNumber : CLI::NonNegativeNumber;
  if (option.min_exclusive || std::isinf(option.max))  // no such option today: CLI11 has no validator for it
    throw std::logic_error(std::string(option.flag) + ": no CLI11 validator for its limits");
  if (option.whole) return CLI::Range(static_cast<int>(option.min), static_cast<int>(option.max));
  return CLI::Range(option.min, option.max);
}

}  // namespace fibrodem::cli
