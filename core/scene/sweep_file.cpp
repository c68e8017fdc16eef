#include "scene/sweep_file.hpp"

#include <fmt/format.h>

#include "util/manifest_error.hpp"
#include "scene/scene.hpp"
#include "scene/schema/schema_check.hpp"

namespace fibrodem {

namespace {

// More points than anyone runs is a mistake in the file (and would exhaust
// memory before a single run).
constexpr double kMaxPoints = 1e6;

std::vector<SweepValues> expand_grid(const json& grid, double seeds) {
  double count = seeds;
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

namespace {

// "seeds": K (the manifest's seed and the K - 1 after it) or a list of seeds.
std::vector<long long> read_seeds(JsonReader& r, long long manifest_seed) {
  const json& value = r.raw("seeds");
  if (value.is_null()) return {};
  std::vector<long long> seeds;
  if (value.is_number_integer() && value.get<long long>() >= 1 && value.get<long long>() <= 100000) {
    for (long long k = 0; k < value.get<long long>(); ++k) seeds.push_back(manifest_seed + k);
    return seeds;
  }
  if (value.is_array() && !value.empty()) {
    for (const auto& s : value) {
      if (!s.is_number_integer() || s.get<long long>() < 0)
        throw ManifestError("seeds", "expected non-negative integer seeds, got " + describe_json(s));
      seeds.push_back(s.get<long long>());
    }
    return seeds;
  }
  throw ManifestError("seeds", "expected a count of seeds (1 to 100000) or a list of seeds, got " + describe_json(value));
}

}  // namespace

SweepFile read_sweep(const json& sweep, const std::function<json(const std::string&)>& read_manifest,
                     const std::vector<std::string>& overrides) {
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
  for (const auto& assignment : overrides) apply_override(file.base, assignment);
  const json& grid = r.raw("grid");
  if (!grid.is_object()) throw ManifestError("grid", "expected an object of dotted paths to lists of values");
  const json& manifest_seed = file.base.contains("seed") ? file.base["seed"] : json(0);
  file.seeds = read_seeds(r, manifest_seed.is_number_integer() ? manifest_seed.get<long long>() : 0);
  r.finish();
  check_against_schema(SchemaKind::sweep, sweep);  // after the reader's own, more specific, checks
  const std::vector<SweepValues> grid_points = expand_grid(grid, file.seeds.empty() ? 1.0 : double(file.seeds.size()));
  for (const auto& point : grid_points) {
    if (file.seeds.empty()) file.points.push_back(point);
    for (long long seed : file.seeds) {
      file.points.push_back(point);
      file.points.back().emplace_back("seed", seed);
    }
  }
  return file;
}

json point_manifest(const SweepFile& sweep, const SweepValues& point) {
  json manifest = sweep.base;
  for (const auto& [path, value] : point) apply_override(manifest, override_assignment(path, value));
  return manifest;
}

}  // namespace fibrodem
