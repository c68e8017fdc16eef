// The manifest's `mechano_electric_feedback` section and its reader.
#pragma once

#include <array>

#include "model/cell_type.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

// Stretch-activated current of the effect mechano_electric_feedback:
// I_SAC = G (lambda - 1)/(lambda_max - 1) (V - E) for lambda = SL/SL_rest > 1
// (the form of Kuijpers et al. 2007, Am J Physiol 292:H2832; values here are
// order-of-magnitude defaults, not the seed paper's, which it does not state).
// `cell_types` switches it on or off per cell type: the types listed get it
// (each must have a myofilament model, the source of its stretch); by default
// every type with a myofilament model.
struct MechanoElectricSpec {
  double G_SAC_nS = 5.0;
  double E_SAC_mV = 0.0;
  double lambda_max = 1.1;
  std::array<bool, kCellTypeNames.size()> on_for_type{};  // by CellType
  bool cell_types_listed = false;  // false: on for every type with a myofilament model
  bool on_for(CellType t) const { return !cell_types_listed || on_for_type[static_cast<int>(t)]; }
};

// Reads the manifest's `mechano_electric_feedback` object (ManifestError
// naming the JSON path).
MechanoElectricSpec read_mechano_electric_spec(JsonReader feedback);

}  // namespace fibrodem
