// What the DEM's files share beyond the solver's class: the um it meets the
// tissue in, and how its messages write numbers.
#pragma once

#include <sstream>
#include <string>

namespace fibrodem {

constexpr double kUm = 1e-6;  // m per um

// A number in the DEM's messages: six significant digits.
inline std::string dem_number(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

}  // namespace fibrodem
