// Numbers as text, every format the project writes in one place: the
// shortest exact text for files read back (CSV, folder lists), a number of
// significant digits for people (messages, reports, axes), a number of
// decimals for tables. Inline, so that the run-time modules (modules/), which
// link no layer, write numbers as the core does.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace fibrodem {

// The shortest text that reads back as the same double (std::to_chars:
// fixed where no longer than scientific); "nan", "inf", "-inf".
inline std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// The same, empty for NaN or infinity (a table's missing value).
inline std::string format_number_or_empty(double value) {
  return std::isfinite(value) ? format_number(value) : "";
}

// `digits` significant digits, trailing zeros dropped: printf's %.<digits>g
// (and an ostream's default format at that precision).
inline std::string significant_digits(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

// `digits` decimals (tables for people); `missing` for NaN or infinity.
inline std::string fixed_decimals(double value, int digits, const std::string& missing = "") {
  if (!std::isfinite(value)) return missing;
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, digits);
  return result.ec == std::errc() ? std::string(buffer, result.ptr) : missing;
}

}  // namespace fibrodem
