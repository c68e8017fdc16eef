#include "model/cell_type_spec.hpp"

namespace fibrodem {

namespace {

// `key`: an object of names (of parameters, or of states) to numbers.
std::map<std::string, double> read_named_numbers(JsonReader& r, const std::string& key, const std::string& what) {
  std::map<std::string, double> numbers;
  const json& object = r.raw(key);
  if (object.is_null()) return numbers;
  if (!object.is_object())
    throw ManifestError(r.path_of(key), "expected an object of " + what + " names to numbers, got " + describe_json(object));
  for (const auto& [name, value] : object.items()) {
    if (!value.is_number())
      throw ManifestError(join_path(r.path_of(key), name), "expected a number, got " + describe_json(value));
    numbers[name] = value.get<double>();
  }
  return numbers;
}

// A model's `parameters` and `initial_state` (per-state overrides of its initial values).
void read_parameters(JsonReader& r, ModelSpec& spec) {
  spec.parameters = read_named_numbers(r, "parameters", "parameter");
  spec.initial_state = read_named_numbers(r, "initial_state", "state");
}

// `"myofilament": "rice"` or `"myofilament": {"model": "rice", "variant": ..., "parameters": {...}}`.
ModelSpec read_myofilament(const json& value, const std::string& path) {
  ModelSpec spec;
  spec.path = path;
  if (value.is_string()) {
    spec.model = value.get<std::string>();
    return spec;
  }
  if (!value.is_object())
    throw ManifestError(path, "expected a model name or an object with \"model\", got " + describe_json(value));
  JsonReader r(value, path);
  spec.model = r.text("model", std::nullopt);
  spec.variant = r.text("variant", std::string());
  read_parameters(r, spec);
  r.finish();
  return spec;
}

}  // namespace

CellTypeSpec read_cell_type_spec(JsonReader r) {
  CellTypeSpec spec;
  spec.path = r.path();
  spec.ionic.path = r.path();
  spec.ionic.model = r.text("model", std::nullopt);
  spec.ionic.variant = r.text("variant", std::string());
  read_parameters(r, spec.ionic);
  if (r.has("myofilament")) spec.myofilament = read_myofilament(r.raw("myofilament"), r.path_of("myofilament"));
  spec.calcium_feedback = r.boolean("calcium_feedback", false);
  if (r.has("settle")) {
    JsonReader settle = r.object("settle");
    spec.settle.ms = settle.number("ms", std::nullopt, 1e-3, 1e7);
    if (settle.has("pacing")) {
      JsonReader pacing = settle.object("pacing");
      spec.settle.period_ms = pacing.number("period_ms", std::nullopt, 1.0, 1e6);
      spec.settle.duration_ms = pacing.number("duration_ms", 2.0, 1e-3, 1e3);
      spec.settle.amplitude_pA = pacing.number("amplitude_pA", std::nullopt, -1e6, 1e6);
      pacing.finish();
    }
    settle.finish();
  }
  r.finish();
  return spec;
}

}  // namespace fibrodem
