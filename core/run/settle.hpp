// cells.TYPE.settle: before t = 0, each cell type's ionic model runs alone (one
// uncoupled cell, its variant, parameters and initial_state overrides), at
// rest or paced, and every cell of the type starts from where it ends: a
// modified model starts from its own rest, not off it. Integrated
// with CVODE (rtol 1e-6, atol 1e-8). The settled states are cached by
// everything that determines them (model, version, variant, parameters,
// initial states, settle spec), in FIBRODEM_CACHE_DIR, else
// $XDG_CACHE_HOME/fibrodem, else ~/.cache/fibrodem (folder settle/).
#pragma once

#include <string>

#include "model/population.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

struct SettleResult {
  std::vector<double> states;  // per state, at the end of the settling
  bool from_cache = false;
  std::string note;  // for run.log and summary.json's notes
};

SettleResult settle_cell(const Population& prototype, const SettleSpec& spec);

}  // namespace fibrodem
