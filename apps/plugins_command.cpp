// `fibrodem plugins`: every cell model found on the search path, with its
// states, parameters, inputs, outputs and variants; then every contact law,
// with its parameters.
#include <iostream>

#include "apps/commands.hpp"
#include "mechanics/contact_law.hpp"
#include "model/model_description.hpp"
#include "model/plugin_registry.hpp"
#include "util/json_reader.hpp"

namespace fibrodem::cli {

namespace {

// "    name = default unit  description", one parameter a line.
void print_parameters(const json& parameters) {
  for (const auto& p : parameters)
    std::cout << "    " << p["name"].get<std::string>() << " = " << p["default"].get<double>() << " "
              << p["unit"].get<std::string>() << "  " << p["description"].get<std::string>() << "\n";
}

void print_text(const json& m) {
  std::cout << m["name"].get<std::string>() << " " << m["version"].get<std::string>() << " ("
            << m["kind"].get<std::string>() << ") - " << m["description"].get<std::string>() << "\n"
            << "  reference: " << m["reference"].get<std::string>() << "\n"
            << "  file: " << m["file"].get<std::string>() << "\n";
  if (!m["variants"].empty()) {
    std::cout << "  variants:";
    for (const auto& v : m["variants"]) std::cout << " " << v["name"].get<std::string>();
    std::cout << " (first = default)\n";
  }
  std::cout << "  states (" << m["states"].size() << "):";
  for (const auto& s : m["states"])
    std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]"
              << (s["gate"].get<bool>() ? "*" : "");
  std::cout << "   (* gate)\n  parameters (" << m["parameters"].size() << "):\n";
  print_parameters(m["parameters"]);
  std::cout << "  inputs:";
  for (const auto& s : m["inputs"]) std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]";
  std::cout << "\n  outputs:";
  for (const auto& s : m["outputs"]) std::cout << " " << s["name"].get<std::string>() << " [" << s["unit"].get<std::string>() << "]";
  std::cout << "\n\n";
}

void print_contact_law(const json& law) {
  std::cout << law["name"].get<std::string>() << " " << law["version"].get<std::string>() << " - "
            << law["description"].get<std::string>() << "\n"
            << "  reference: " << law["reference"].get<std::string>() << "\n"
            << "  file: " << law["file"].get<std::string>() << "\n"
            << "  parameters (" << law["parameters"].size() << "; mechanics.contact_law_parameters):\n";
  print_parameters(law["parameters"]);
  std::cout << "\n";
}

}  // namespace

int plugins_command(bool as_json) {
  PluginRegistry registry;
  std::vector<std::string> errors;
  const json all = describe_available_models(registry, errors);
  // (The JSON keeps its form, an array of cell models: other tools read it.)
  const json laws = as_json ? json::array() : describe_available_contact_laws(errors);
  for (const auto& e : errors) std::cerr << "error: " << e << "\n";
  if (as_json) {
    std::cout << all.dump(2) << "\n";
    return errors.empty() ? 0 : 3;
  }
  std::cout << "search path:";
  for (const auto& p : registry.search_path()) std::cout << " " << p.string();
  std::cout << "\n\n";
  for (const auto& m : all) print_text(m);
  std::cout << "contact laws (mechanics.contact_law):\n\n";
  for (const auto& law : laws) print_contact_law(law);
  return errors.empty() ? 0 : 3;
}

}  // namespace fibrodem::cli
