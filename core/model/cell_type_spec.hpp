// The manifest's `cells.TYPE` sections: each cell type's ionic model, its
// variant and parameters, a myofilament model, and a settle before t = 0;
// and their reader.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "util/json_reader.hpp"

namespace fibrodem {

// One model of a cell type: a plugin, its variant, parameter overrides.
struct ModelSpec {
  std::string model;
  std::string variant;  // empty: the model's default variant
  std::map<std::string, double> parameters;
  std::map<std::string, double> initial_state;  // per state, over the model's (and variant's) initial value
  std::string path;     // JSON path of this model's object, for errors found later
};

// cells.TYPE.settle (run/settle.hpp): the ionic model alone for ms before
// t = 0, at rest, or paced by pulses every period_ms from t = 0 when given.
struct SettleSpec {
  double ms = 0;  // 0: no settling
  double period_ms = 0, duration_ms = 2, amplitude_pA = 0;
};

struct CellTypeSpec {
  ModelSpec ionic;
  SettleSpec settle;
  std::optional<ModelSpec> myofilament;  // driven by the ionic model's Ca_i
  bool calcium_feedback = false;  // troponin buffering fed back into the host's Ca_i
  std::string path;
};

// Reads one `cells.TYPE` object (ManifestError naming the JSON path).
CellTypeSpec read_cell_type_spec(JsonReader cell_type);

}  // namespace fibrodem
