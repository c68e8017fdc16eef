#include "stimulus/stimulus_spec.hpp"

#include <limits>

#include "tissue/tissue_builder.hpp"

namespace fibrodem {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// A region target: fractions of the bounding box (x_min_frac..), a rectangle
// in mm (x_min_mm, x_max_mm, y_min_mm, y_max_mm, all four) or a disc in mm
// (center_x_mm, center_y_mm, radius_mm); one form per region.
StimulusTarget read_region(const json& t, const std::string& path) {
  StimulusTarget target;
  target.kind = StimulusTarget::Kind::region;
  JsonReader r(t, path);
  const bool rect = r.has("x_min_mm") || r.has("x_max_mm") || r.has("y_min_mm") || r.has("y_max_mm");
  const bool circle = r.has("center_x_mm") || r.has("center_y_mm") || r.has("radius_mm");
  const bool fractions = r.has("x_min_frac") || r.has("x_max_frac") || r.has("y_min_frac") || r.has("y_max_frac");
  if (int(rect) + int(circle) + int(fractions) > 1)
    throw ManifestError(path, "expected one form of region: fractions (x_min_frac..), a rectangle in mm "
                              "(x_min_mm, x_max_mm, y_min_mm, y_max_mm) or a circle (center_x_mm, center_y_mm, "
                              "radius_mm), got keys of several");
  constexpr double kFar_mm = 1e6;
  if (rect) {
    target.shape = StimulusTarget::Shape::rect_mm;
    target.x_min_mm = r.number("x_min_mm", std::nullopt, -kFar_mm, kFar_mm);
    target.x_max_mm = r.number("x_max_mm", std::nullopt, -kFar_mm, kFar_mm);
    target.y_min_mm = r.number("y_min_mm", std::nullopt, -kFar_mm, kFar_mm);
    target.y_max_mm = r.number("y_max_mm", std::nullopt, -kFar_mm, kFar_mm);
    if (target.x_min_mm > target.x_max_mm)
      throw ManifestError(r.path_of("x_max_mm"), "expected x_max_mm >= x_min_mm (" + describe_json(target.x_min_mm) +
                                                     "), got " + describe_json(target.x_max_mm));
    if (target.y_min_mm > target.y_max_mm)
      throw ManifestError(r.path_of("y_max_mm"), "expected y_max_mm >= y_min_mm (" + describe_json(target.y_min_mm) +
                                                     "), got " + describe_json(target.y_max_mm));
  } else if (circle) {
    target.shape = StimulusTarget::Shape::circle_mm;
    target.center_x_mm = r.number("center_x_mm", std::nullopt, -kFar_mm, kFar_mm);
    target.center_y_mm = r.number("center_y_mm", std::nullopt, -kFar_mm, kFar_mm);
    target.radius_mm = r.number("radius_mm", std::nullopt, 1e-6, kFar_mm);
  } else {
    target.x_min_frac = r.number("x_min_frac", 0.0, 0.0, 1.0);
    target.x_max_frac = r.number("x_max_frac", 1.0, 0.0, 1.0);
    target.y_min_frac = r.number("y_min_frac", 0.0, 0.0, 1.0);
    target.y_max_frac = r.number("y_max_frac", 1.0, 0.0, 1.0);
    if (target.x_min_frac > target.x_max_frac || target.y_min_frac > target.y_max_frac)
      throw ManifestError(path, "expected min fractions <= max fractions");
  }
  if (r.has("type")) target.region_type = read_cell_type(r, "type", CellType::myocyte);
  r.finish();
  return target;
}

StimulusTarget read_target(const json& t, const std::string& path) {
  StimulusTarget target;
  if (t.is_string()) {
    target.kind = StimulusTarget::Kind::cell_type;
    const std::string s = t.get<std::string>();
    if (s == "myocyte") target.type = CellType::myocyte;
    else if (s == "fibroblast") target.type = CellType::fibroblast;
    else
      throw ManifestError(path, "expected a cell type (\"myocyte\" or \"fibroblast\"), a list of "
                                "cell indices or a region object, got " + describe_json(t));
  } else if (t.is_array()) {
    target.kind = StimulusTarget::Kind::cells;
    target.cells = read_cell_indices(t, path);
    if (target.cells.empty()) throw ManifestError(path, "expected at least one cell index");
  } else if (t.is_object()) {
    target = read_region(t, path);
  } else {
    throw ManifestError(path, "expected a cell type, a list of cell indices or a region object, got " +
                                  describe_json(t));
  }
  return target;
}

}  // namespace

StimulusSpec read_stimulus_spec(JsonReader r) {
  StimulusSpec s;
  s.path = r.path();
  if (!r.has("target")) throw ManifestError(r.path_of("target"), "required value is missing");
  s.target = read_target(r.raw("target"), r.path_of("target"));
  s.start_ms = r.number("start_ms", 0.0, 0.0, kInf);
  s.duration_ms = r.number("duration_ms", 2.0, 1e-9, kInf);
  s.amplitude_pA = r.number("amplitude_pA", std::nullopt, -1e7, 1e7);
  s.period_ms = r.number("period_ms", 0.0, 0.0, kInf);
  const long long unlimited = std::numeric_limits<int>::max();
  s.count = r.integer("count", s.period_ms > 0 ? unlimited : 1, 1, unlimited);
  if (s.period_ms > 0 && s.period_ms < s.duration_ms)
    throw ManifestError(r.path_of("period_ms"), "expected a period >= duration_ms (" +
                                                    std::to_string(s.duration_ms) + " ms)");
  if (s.period_ms == 0 && s.count > 1)
    throw ManifestError(r.path_of("count"), "a count above 1 needs a period_ms > 0");
  r.finish();
  return s;
}

}  // namespace fibrodem
