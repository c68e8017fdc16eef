// Conformance checks of a cell-model plugin (`fibrodem check-plugin`): what a
// plugin author runs before trusting its results. Each check probes the model
// through the same BlockView calls a run makes and reports pass or fail with
// every fault it found, naming states, values and variants.
//
// The checks (plugin_check.cpp says how each probes):
//   metadata            names present and unique, bounds ordered around the initial
//                       values, indices in range, capacitance > 0, variants naming
//                       what the model has, the contract of its kind
//   derivatives written every state's a and b and every output written by
//                       evaluate() (the arrays are poisoned first), nothing
//                       written outside [begin, end)
//   finite at rest      a, b, outputs finite at the initial state, per variant
//   finite over V       the same with V swept from -120 to +80 mV (ionic)
//   voltage_only gates  their a and b unchanged when any other state or input moves
//   linear forms        gates: b <= 0, y_inf = -a/b within the bounds, b the slope
//                       of a + b y in y (finite difference); other states with
//                       b != 0: b of the slope's sign
//   bounds over a beat  one paced beat (Rush-Larsen, 0.01 ms) keeps every state
//                       within its bounds, per variant
//   block = single cell SIMD block results equal each cell evaluated alone, bit
//                       for bit; the scalar path agrees to 1e-9; evaluation repeatable
#pragma once

#include <string>
#include <vector>

#include "model/cell_model.hpp"
#include "model/simd.hpp"

namespace fibrodem {

struct PluginCheck {
  std::string name;
  std::vector<std::string> faults;  // empty: passed
  std::string skipped;              // non-empty: not run, and why
  std::string note;                 // what was seen, for the author (e.g. the range of V over the beat)
  bool passed() const { return faults.empty(); }
};

struct PluginCheckReport {
  std::vector<PluginCheck> checks;
  bool passed() const;
  std::size_t failed_count() const;
};

// Cells in the blocks the checks evaluate: two full lane groups and a partial
// one (11 with AVX2, 19 with AVX-512: the build is for its host's CPU).
inline constexpr std::size_t kProbeCells = 2 * simd::kLanes + 3;

PluginCheckReport check_plugin(const CellModel& model);

}  // namespace fibrodem
