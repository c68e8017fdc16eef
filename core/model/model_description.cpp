#include "model/model_description.hpp"

#include <cmath>

namespace fibrodem {

using json = nlohmann::json;

namespace {
// JSON has no infinity: an unbounded side (the +-1e300 default) is null.
json bound(double value) { return std::abs(value) >= 1e300 ? json(nullptr) : json(value); }
}  // namespace

json describe_parameters(const std::vector<ParameterInfo>& parameters) {
  json all = json::array();
  for (const auto& p : parameters)
    all.push_back({{"name", p.name}, {"unit", p.unit}, {"default", p.default_value}, {"description", p.description}});
  return all;
}

json describe_model(const ModelInfo& info, const PluginRecord& record) {
  json m = {{"name", info.name}, {"version", info.version}, {"description", info.description},
            {"reference", info.reference}, {"file", record.file.string()}, {"sha256", record.sha256},
            {"kind", info.kind == ModelKind::ionic ? "ionic" : "myofilament"}};
  m["states"] = json::array();
  for (const auto& s : info.states)
    m["states"].push_back({{"name", s.name}, {"unit", s.unit}, {"initial", s.initial}, {"lower", bound(s.lower)},
                           {"upper", bound(s.upper)}, {"gate", s.gate}});
  m["parameters"] = describe_parameters(info.parameters);
  m["inputs"] = json::array();
  for (const auto& s : info.inputs) m["inputs"].push_back({{"name", s.name}, {"unit", s.unit}});
  m["outputs"] = json::array();
  for (const auto& s : info.outputs) m["outputs"].push_back({{"name", s.name}, {"unit", s.unit}});
  m["variants"] = json::array();
  for (const auto& v : info.variants)
    m["variants"].push_back({{"name", v.name}, {"description", v.description}, {"parameters", v.parameters},
                             {"initial_state", v.initial_state}});
  return m;
}

json describe_available_models(PluginRegistry& registry, std::vector<std::string>& errors) {
  json all = json::array();
  for (const auto& name : registry.available()) {
    try {
      auto model = registry.load(name);
      PluginRecord record;
      for (const auto& r : registry.loaded())
        if (r.name == name) record = r;
      all.push_back(describe_model(model->info(), record));
    } catch (const std::exception& e) {
      errors.push_back(e.what());
    }
  }
  return all;
}

}  // namespace fibrodem
