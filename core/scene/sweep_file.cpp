#include "scene/sweep_file.hpp"

#include <fmt/format.h>

#include "scene/manifest_error.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

namespace {

// More points than anyone runs is a mistake in the file (and would exhaust
// memory before a single run).
constexpr double kMaxPoints = 1e6;

std::vector<SweepValues> expand_grid(const json& grid) {
  double count = 1;
  for (const auto& [path, values] : grid.items()) {
    if (!values.is_array() || values.empty())
      throw ManifestError("grid." + path, "expected a non-empty list of values");
    count *= static_cast<double>(values.size());
  }
  if (count > kMaxPoints)
    throw ManifestError("grid", "its product has " + fmt::format("{:g}", count) + " points; at most " +
                                    fmt::format("{:g}", kMaxPoints) + " are accepted");
  std::vector<SweepValues> points(1);
  for (const auto& [path, values] : grid.items()) {
    std::vector<SweepValues> next;
    for (const auto& point : points)
      for (const auto& v : values) {
        SweepValues p = point;
        p.emplace_back(path, v);
        next.push_back(std::move(p));
      }
    points = std::move(next);
  }
  return points;
}

}  // namespace

std::string override_assignment(const std::string& path, const json& value) {
  return path + "=" + value.dump(-1, ' ', false, json::error_handler_t::replace);
}

SweepFile read_sweep(const json& sweep, const std::function<json(const std::string&)>& read_manifest) {
  if (!sweep.is_object()) throw ManifestError("", "expected a sweep object, got " + describe_json(sweep));
  JsonReader r(sweep, "");
  r.integer("fibrodem_sweep", std::nullopt, 1, 1);
  SweepFile file;
  file.base = read_manifest(r.text("manifest", std::nullopt));
  if (!file.base.is_object())
    throw ManifestError("manifest", "expected the manifest file to hold a JSON object, got " + describe_json(file.base));
  const json& fixed = r.raw("set");
  if (!fixed.is_null()) {
    if (!fixed.is_object()) throw ManifestError("set", "expected an object of dotted paths to values");
    for (const auto& [path, value] : fixed.items()) apply_override(file.base, override_assignment(path, value));
  }
  const json& grid = r.raw("grid");
  if (!grid.is_object()) throw ManifestError("grid", "expected an object of dotted paths to lists of values");
  r.finish();
  file.points = expand_grid(grid);
  return file;
}

json point_manifest(const SweepFile& sweep, const SweepValues& point) {
  json manifest = sweep.base;
  for (const auto& [path, value] : point) apply_override(manifest, override_assignment(path, value));
  return manifest;
}

}  // namespace fibrodem
