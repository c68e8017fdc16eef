// `fibrodem plugins`: every cell model found on the search path, with its
// states, parameters, inputs, outputs and variants.
#include <iostream>

#include "apps/commands.hpp"
#include "model/plugin_registry.hpp"
#include "scene/json_reader.hpp"

namespace fibrodem::cli {

namespace {

json describe(const ModelInfo& info, const PluginRecord& record) {
  json m = {{"name", info.name}, {"version", info.version}, {"description", info.description},
            {"reference", info.reference}, {"file", record.file.string()}, {"sha256", record.sha256},
            {"kind", info.kind == ModelKind::ionic ? "ionic" : "myofilament"}};
  for (const auto& s : info.states)
    m["states"].push_back({{"name", s.name}, {"unit", s.unit}, {"initial", s.initial}, {"gate", s.gate}});
  for (const auto& p : info.parameters)
    m["parameters"].push_back({{"name", p.name}, {"unit", p.unit}, {"default", p.default_value},
                               {"description", p.description}});
  for (const auto& s : info.inputs) m["inputs"].push_back({{"name", s.name}, {"unit", s.unit}});
  for (const auto& s : info.outputs) m["outputs"].push_back({{"name", s.name}, {"unit", s.unit}});
  for (const auto& v : info.variants) m["variants"].push_back({{"name", v.name}, {"description", v.description}});
  return m;
}

void print_text(const json& m) {
  std::cout << m["name"].get<std::string>() << " " << m["version"].get<std::string>() << " ("
            << m["kind"].get<std::string>() << ") - " << m["description"].get<std::string>() << "\n"
            << "  reference: " << m["reference"].get<std::string>() << "\n"
            << "  file: " << m["file"].get<std::string>() << "\n";
  if (m.contains("variants")) {
    std::cout << "  variants:";
    for (const auto& v : m["variants"]) std::cout << " " << v["name"].get<std::string>();
    std::cout << " (first = default)\n";
  }
  std::cout << "  states (" << m["states"].size() << "):";
  for (const auto& s : m["states"])
    std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]"
              << (s["gate"].get<bool>() ? "*" : "");
  std::cout << "   (* gate)\n  parameters (" << m["parameters"].size() << "):\n";
  for (const auto& p : m["parameters"])
    std::cout << "    " << p["name"].get<std::string>() << " = " << p["default"].get<double>() << " "
              << p["unit"].get<std::string>() << "  " << p["description"].get<std::string>() << "\n";
  std::cout << "  inputs:";
  for (const auto& s : m["inputs"]) std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]";
  std::cout << "\n  outputs:";
  for (const auto& s : m["outputs"]) std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]";
  std::cout << "\n\n";
}

}  // namespace

int plugins_command(bool as_json) {
  PluginRegistry registry;
  json all = json::array();
  int failures = 0;
  for (const auto& name : registry.available()) {
    try {
      auto model = registry.load(name);
      PluginRecord record;
      for (const auto& r : registry.loaded())
        if (r.name == name) record = r;
      all.push_back(describe(model->info(), record));
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      ++failures;
    }
  }
  if (as_json) std::cout << all.dump(2) << "\n";
  else {
    std::cout << "search path:";
    for (const auto& p : registry.search_path()) std::cout << " " << p.string();
    std::cout << "\n\n";
    for (const auto& m : all) print_text(m);
  }
  return failures ? 3 : 0;
}

}  // namespace fibrodem::cli
