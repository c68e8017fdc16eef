// What the DEM's files share beyond the solver's class: the um it meets the
// tissue in (their messages write numbers with util/number_text.hpp).
#pragma once

namespace fibrodem {

constexpr double kUm = 1e-6;  // m per um

}  // namespace fibrodem
