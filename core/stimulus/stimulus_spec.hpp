// The manifest's `stimulus` entries: which cells each pulse train drives
// (a cell type, listed cells, or a region of the tissue) and when. Read by
// scene/scene.cpp; turned into currents by stimulus/stimulus.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model/cell_type.hpp"

namespace fibrodem {

struct StimulusTarget {
  enum class Kind { cell_type, cells, region } kind = Kind::cell_type;
  CellType type = CellType::myocyte;
  std::vector<int> cells;
  // region, as fractions of the tissue's bounding box; optional type filter
  double x_min_frac = 0, x_max_frac = 1, y_min_frac = 0, y_max_frac = 1;
  std::optional<CellType> region_type;
};

struct StimulusSpec {
  StimulusTarget target;
  double start_ms = 0, duration_ms = 2, amplitude_pA = 2000;
  double period_ms = 0;  // 0: a single train entry without repetition
  long long count = 1;
  std::string path;
};

}  // namespace fibrodem
