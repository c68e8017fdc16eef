// coupling.regions: parts of the tissue whose gap junctions conduct
// otherwise than the rest (bundles, border zones). A junction belongs to a
// region when the midpoint of the two cells' centres lies in it; where
// regions overlap, the last one listed that holds the midpoint sets the
// junction's conductances (a later region overrides an earlier one).
#pragma once

#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// A junction's conductance by the cells it joins [nS].
struct JunctionConductances {
  double D_m_nS = 1000;       // two myocytes, end to end (along the fibres)
  double D_m_side_nS = 1000;  // two myocytes, side to side (across the fibres)
  double D_f_nS = 2;          // any pair with a fibroblast
};

struct CouplingRegion {
  enum class Shape { rectangle, ellipse };  // ellipse: the one inscribed in the rectangle
  Shape shape = Shape::rectangle;
  double x_min_um = 0, x_max_um = 0, y_min_um = 0, y_max_um = 0;
  JunctionConductances g_nS;  // of the junctions it holds
  std::string path;           // coupling.regions[i], for messages
  bool contains(double x_um, double y_um) const;
};

// The index of the last region that holds the point (x, y), or -1 if none does.
int region_holding(const std::vector<CouplingRegion>& regions, double x_um, double y_um);

// Reads `key` of r, [min, max] in mm with min < max, as um (ManifestError
// naming the key's path otherwise).
void read_span_mm(JsonReader& r, const std::string& key, double& min_um, double& max_um);

// Reads coupling.regions (`regions`, a list): each a `shape`, `x_mm` and
// `y_mm` ([min, max]) and either `scale` (every conductance of `base`
// times it) or any of D_m_nS, D_m_side_nS, D_f_nS (the others from `base`;
// D_m_side_nS, unset, is the region's D_m_nS if it sets that, as at the top).
std::vector<CouplingRegion> read_coupling_regions(const json& regions, const std::string& path,
                                                  const JunctionConductances& base);

}  // namespace fibrodem
