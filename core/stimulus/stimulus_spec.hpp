// The manifest's `stimulus` entries: which cells each pulse train drives
// (a cell type, listed cells, or a region of the tissue) and when, and their
// reader; stimulus/stimulus.hpp turns them into currents. Protocols
// (docs/topics/arrhythmia.md): cross-field S1-S2 is a thin edge rectangle then a
// quadrant rectangle; point S1-S2-S3 and burst pacing are circles with
// trains of given period and count.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model/cell_type.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

struct StimulusTarget {
  enum class Kind { cell_type, cells, region } kind = Kind::cell_type;
  CellType type = CellType::myocyte;
  std::vector<int> cells;
  // A region selects the cells whose centre lies in it (edges included):
  //   fractions  a rectangle in fractions of the tissue's bounding box
  //   rect_mm    a rectangle in the tissue's coordinates [mm]
  //   circle_mm  a disc in the tissue's coordinates [mm]
  // with an optional cell type filter.
  enum class Shape { fractions, rect_mm, circle_mm } shape = Shape::fractions;
  double x_min_frac = 0, x_max_frac = 1, y_min_frac = 0, y_max_frac = 1;
  double x_min_mm = 0, x_max_mm = 0, y_min_mm = 0, y_max_mm = 0;
  double center_x_mm = 0, center_y_mm = 0, radius_mm = 0;
  std::optional<CellType> region_type;
};

struct StimulusSpec {
  StimulusTarget target;
  double start_ms = 0, duration_ms = 2, amplitude_pA = 2000;
  double period_ms = 0;  // 0: a single train entry without repetition
  long long count = 1;
  std::string path;
};

// Reads one entry of the manifest's `stimulus` list (ManifestError naming
// the JSON path).
StimulusSpec read_stimulus_spec(JsonReader stimulus);

}  // namespace fibrodem
