#include "mechanics/contact_law.hpp"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include "model/model_description.hpp"
#include "model/plugin_registry.hpp"

namespace fibrodem {

namespace {

std::string file_of(const std::string& name) { return kContactLawFilePrefix + name + ".so"; }

// Laws loaded so far in this process, by name (a law is stateless: one
// instance serves every solver and thread).
struct LoadedLaws {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const ContactLaw>> laws;
  std::map<std::string, ContactLawRecord> records;
};
LoadedLaws& loaded_laws() {
  static LoadedLaws loaded;
  return loaded;
}

void check_law_info(const ContactLawInfo& info, const std::string& name, const std::string& file) {
  const std::string who = "contact law plugin " + file + ": ";
  if (info.name != name) throw PluginError(who + "calls its law '" + info.name + "', expected '" + name + "'");
  std::map<std::string, int> seen;
  for (const auto& p : info.parameters) {
    if (p.name.empty()) throw PluginError(who + "a parameter has no name");
    if (seen[p.name]++) throw PluginError(who + "two parameters are named '" + p.name + "'");
    if (!std::isfinite(p.default_value))
      throw PluginError(who + "parameter '" + p.name + "' defaults to a value that is not finite");
  }
}

}  // namespace

std::shared_ptr<const ContactLaw> load_contact_law(const std::string& name) {
  LoadedLaws& loaded = loaded_laws();
  std::lock_guard<std::mutex> lock(loaded.mutex);
  if (auto it = loaded.laws.find(name); it != loaded.laws.end()) return it->second;
  const PluginRegistry registry;  // the search path as the environment says now
  const OpenedPlugin plugin = registry.open(file_of(name), "fibrodem_create_contact_law",
                                            "fibrodem_contact_law_abi_version", kContactLawAbiVersion,
                                            "FIBRODEM_CONTACT_LAW_PLUGIN");
  ContactLaw* raw = reinterpret_cast<ContactLaw* (*)()>(plugin.factory)();
  if (raw == nullptr) throw PluginError("contact law plugin " + plugin.file.string() + " created no law");
  // The deleter owns the library: it is unloaded only after the law is gone.
  std::shared_ptr<const ContactLaw> law(raw, [library = plugin.library](const ContactLaw* l) { delete l; });
  check_law_info(law->info(), name, plugin.file.string());
  loaded.laws[name] = law;
  loaded.records[name] = {name, law->info().version, plugin.file.string(), sha256_of_file(plugin.file)};
  return law;
}

ContactLawRecord contact_law_record(const std::string& name) {
  LoadedLaws& loaded = loaded_laws();
  std::lock_guard<std::mutex> lock(loaded.mutex);
  const auto it = loaded.records.find(name);
  if (it == loaded.records.end()) throw PluginError("contact law '" + name + "' was not loaded");
  return it->second;
}

std::vector<std::string> available_contact_laws() {
  return PluginRegistry().available(kContactLawFilePrefix);
}

nlohmann::json describe_available_contact_laws(std::vector<std::string>& errors) {
  nlohmann::json all = nlohmann::json::array();
  for (const auto& name : available_contact_laws()) {
    try {
      const ContactLawInfo& info = load_contact_law(name)->info();
      const ContactLawRecord record = contact_law_record(name);
      all.push_back({{"name", info.name},
                     {"version", info.version},
                     {"description", info.description},
                     {"reference", info.reference},
                     {"file", record.file},
                     {"sha256", record.sha256},
                     {"parameters", describe_parameters(info.parameters)}});
    } catch (const std::exception& e) {
      errors.push_back(e.what());
    }
  }
  return all;
}

std::vector<double> contact_law_parameter_values(const ContactLawInfo& law, const DemSpec& spec) {
  const std::map<std::string, double> legacy = {
      {"damping_ratio_normal", spec.damping_ratio_normal}, {"damping_ratio_shear", spec.damping_ratio_shear},
      {"tensile_strength_N", spec.tensile_strength_N},     {"shear_strength_N", spec.shear_strength_N},
      {"friction", spec.friction},                         {"bond_radius_multiplier", spec.bond_radius_multiplier}};
  std::vector<double> values;
  std::string names;
  for (const auto& p : law.parameters) {
    const auto it = legacy.find(p.name);
    values.push_back(it != legacy.end() ? it->second : p.default_value);
    names += (names.empty() ? "" : ", ") + p.name;
  }
  for (const auto& [name, value] : spec.contact_law_parameters) {
    std::size_t k = 0;
    while (k < law.parameters.size() && law.parameters[k].name != name) ++k;
    if (k == law.parameters.size())
      throw std::invalid_argument("contact law " + law.name + " has no parameter '" + name +
                                  "' (it has: " + (names.empty() ? "none" : names) + ")");
    if (!std::isfinite(value))
      throw std::invalid_argument("contact law parameter '" + name + "' is not a finite number");
    values[k] = value;
  }
  return values;
}

std::unique_ptr<BoundContactLaw> make_contact_law(const DemSpec& spec) {
  std::shared_ptr<const ContactLaw> law = load_contact_law(spec.contact_law);
  std::vector<double> values = contact_law_parameter_values(law->info(), spec);
  return std::make_unique<BoundContactLaw>(std::move(law), std::move(values));
}

}  // namespace fibrodem
