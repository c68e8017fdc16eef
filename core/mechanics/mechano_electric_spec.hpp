// The manifest's `mechano_electric_feedback` section and its reader.
#pragma once

#include "util/json_reader.hpp"

namespace fibrodem {

// Stretch-activated current of the effect mechano_electric_feedback:
// I_SAC = G (lambda - 1)/(lambda_max - 1) (V - E) for lambda = SL/SL_rest > 1
// (the form of Kuijpers et al. 2007, Am J Physiol 292:H2832; values here are
// order-of-magnitude defaults, not the seed paper's, which it does not state).
struct MechanoElectricSpec {
  double G_SAC_nS = 5.0;
  double E_SAC_mV = 0.0;
  double lambda_max = 1.1;
};

// Reads the manifest's `mechano_electric_feedback` object (ManifestError
// naming the JSON path).
MechanoElectricSpec read_mechano_electric_spec(JsonReader feedback);

}  // namespace fibrodem
