#include "mechanics/mechano_electric_spec.hpp"

namespace fibrodem {

MechanoElectricSpec read_mechano_electric_spec(JsonReader r) {
  MechanoElectricSpec m;
  m.G_SAC_nS = r.number("G_SAC_nS", m.G_SAC_nS, 0.0, 1e6);
  m.E_SAC_mV = r.number("E_SAC_mV", m.E_SAC_mV, -200.0, 200.0);
  m.lambda_max = r.number("lambda_max", m.lambda_max, 1.0 + 1e-6, 10.0);
  r.finish();
  return m;
}

}  // namespace fibrodem
