// Numbers as text (util/number_text.hpp), the one set of formats the core,
// the command line and the run-time modules write numbers with.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "util/number_text.hpp"

using namespace fibrodem;

TEST_CASE("format_number: the shortest text that reads back, fixed where as short") {
  CHECK(format_number(0.1) == "0.1");
  CHECK(format_number(1200000) == "1200000");  // as short as 1.2e+06: fixed
  CHECK(format_number(1e-7) == "1e-07");
  CHECK(std::stod(format_number(0.1 + 0.2)) == 0.1 + 0.2);
  CHECK(format_number(std::numeric_limits<double>::quiet_NaN()) == "nan");
  CHECK(format_number(-std::numeric_limits<double>::infinity()) == "-inf");
  CHECK(format_number_or_empty(std::numeric_limits<double>::infinity()) == "");
}

TEST_CASE("significant_digits is printf's %.Ng, and an ostream's default format at that precision") {
  // The formats it replaced: ostream precision 6, 10 and 12 (messages,
  // folder names, schema limits), fmt's {:.3g} and {:.6g}.
  for (double x : {0.0886707, 684.763, 500.0, 1234567.0, 1e-5, -2.5e-12, 189.0625, 1.0 / 3}) {
    for (int digits : {2, 3, 4, 6, 10, 12}) {
      std::ostringstream stream;
      stream.precision(digits);
      stream << x;
      CHECK(significant_digits(x, digits) == stream.str());
    }
  }
  CHECK(significant_digits(0.0886707, 3) == "0.0887");
  CHECK(significant_digits(1234567.0, 6) == "1.23457e+06");
  CHECK(significant_digits(250.0, 10) == "250");
}

TEST_CASE("fixed_decimals: a number of decimals, `missing` for NaN or infinity") {
  CHECK(fixed_decimals(2.345, 1) == "2.3");
  CHECK(fixed_decimals(-0.5, 2) == "-0.50");
  CHECK(fixed_decimals(std::numeric_limits<double>::quiet_NaN(), 2, "n/a") == "n/a");
}
