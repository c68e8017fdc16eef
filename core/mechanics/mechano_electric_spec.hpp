// The manifest's `mechano_electric_feedback` section and its reader.
#pragma once

#include <array>

#include "model/cell_type.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

// Stretch-activated current of the effect mechano_electric_feedback:
// I_SAC = G (lambda - 1)/(lambda_max - 1) (V - E) for lambda > 1 (the form
// of Kuijpers et al. 2007, Am J Physiol 292:H2832; values here are
// order-of-magnitude defaults, not the seed paper's, which it does not state).
// lambda is, by `stretch`:
// - sarcomere: the cell's own SL / SL_rest from its myofilament model, which
//   an unloaded cell only shortens;
// - tissue: the cell's fibre stretch in the deforming DEM tissue,
//   sqrt(1 + 2 E_yy) of its Green-Lagrange strain from its neighbours'
//   displacements (measure/cell_strain.hpp): a resting cell pulled by
//   contracting neighbours is stretched (Weise & Panfilov 2011's mechanism).
// `cell_types` switches it on or off per cell type: the types listed get it
// (with `sarcomere` each must have a myofilament model, the source of its
// stretch); by default every type with a myofilament model.
enum class StretchSource { sarcomere, tissue };

struct MechanoElectricSpec {
  double G_SAC_nS = 5.0;
  double E_SAC_mV = 0.0;
  double lambda_max = 1.1;
  StretchSource stretch = StretchSource::sarcomere;
  std::array<bool, kCellTypeNames.size()> on_for_type{};  // by CellType, as listed
  bool cell_types_listed = false;  // false: on for every type with a myofilament model (the run decides)
  bool listed(CellType t) const { return on_for_type[static_cast<int>(t)]; }
};

// Reads the manifest's `mechano_electric_feedback` object (ManifestError
// naming the JSON path).
MechanoElectricSpec read_mechano_electric_spec(JsonReader feedback);

}  // namespace fibrodem
