// The manifest's `coupling` section: the gap-junction conductances (seed
// paper eq. 5) and how the coupling is stepped, and its reader.
#pragma once

#include <string>
#include <vector>

#include <optional>

#include "coupling/coupling_field.hpp"
#include "coupling/coupling_region.hpp"

namespace fibrodem {

struct CouplingSpec {
  bool present = false;  // the manifest has a `coupling` section
  std::string law = "gap_junction";
  double D_m_nS = 1000.0;  // myocyte-myocyte (seed paper eq. 5), end to end
  // Myocyte-myocyte side to side (across the fibres): the tissue's
  // anisotropy beyond what the cells' shape gives; D_m_nS unless set.
  double D_m_side_nS = 1000.0;
  double D_f_nS = 2.0;     // any pair with a fibroblast
  std::string scheme = "explicit";  // explicit | implicit (backward Euler)
  double dt_ms = 0;                 // coupling's own step (a multiple of solver.dt_ms); 0: every cell step
  std::vector<CouplingRegion> regions;  // coupling.regions, in order (a later one overrides)
  std::optional<CouplingField> field;   // coupling.field: a scale on top of the above
  JunctionConductances conductances() const { return {D_m_nS, D_m_side_nS, D_f_nS}; }
};

// Reads the manifest's `coupling` object (ManifestError naming the JSON path).
// A region that holds no junction is found when the coupling is built
// (GapJunctionCoupler), which knows the tissue.
CouplingSpec read_coupling_spec(JsonReader coupling);

}  // namespace fibrodem
