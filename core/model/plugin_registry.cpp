#include "model/plugin_registry.hpp"

#include "io/sha256.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace fibrodem {
namespace fs = std::filesystem;

namespace {
constexpr const char* kPrefix = "libfibrodem_";
constexpr const char* kSuffix = ".so";

std::string join_paths(const std::vector<fs::path>& paths) {
  std::string s;
  for (const auto& p : paths) s += (s.empty() ? "" : ", ") + p.string();
  return s.empty() ? "(empty)" : s;
}
}  // namespace

std::string sha256_of_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw PluginError("cannot read " + file.string() + " to hash it");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return sha256_hex(bytes.str());
}

std::vector<fs::path> PluginRegistry::default_search_path() {
  return search_path_beside(boost::dll::program_location().parent_path());
}

std::vector<fs::path> PluginRegistry::search_path_beside(const fs::path& exe_dir) {
  std::vector<fs::path> path;
  if (const char* env = std::getenv("FIBRODEM_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string dir;
    while (std::getline(ss, dir, ':'))
      if (!dir.empty()) path.emplace_back(dir);
  }
  path.push_back(exe_dir / "plugins");
  path.push_back(exe_dir.parent_path() / "plugins");
  path.push_back(exe_dir.parent_path() / "lib" / "fibrodem" / "plugins");
  return path;
}

PluginRegistry::PluginRegistry(std::vector<fs::path> search_path)
    : search_path_(std::move(search_path)) {}

std::vector<std::string> PluginRegistry::available() const {
  std::set<std::string> names;
  for (const auto& dir : search_path_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string file = entry.path().filename().string();
      if (file.rfind(kPrefix, 0) == 0 && file.size() > std::string(kPrefix).size() + 3 &&
          file.substr(file.size() - 3) == kSuffix)
        names.insert(file.substr(std::string(kPrefix).size(),
                                 file.size() - std::string(kPrefix).size() - 3));
    }
  }
  return {names.begin(), names.end()};
}

fs::path PluginRegistry::find_file(const std::string& name) const {
  for (const auto& dir : search_path_) {
    const fs::path candidate = dir / (kPrefix + name + kSuffix);
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  std::string found;
  for (const auto& n : available()) found += (found.empty() ? "" : ", ") + n;
  throw PluginError("no cell-model plugin named '" + name + "' (looked for " + kPrefix + name +
                    kSuffix + " in: " + join_paths(search_path_) +
                    "; models found: " + (found.empty() ? "none" : found) +
                    "; set FIBRODEM_PLUGIN_PATH to add a directory)");
}

std::shared_ptr<const CellModel> PluginRegistry::load(const std::string& name) {
  if (auto it = models_.find(name); it != models_.end()) return it->second;
  const fs::path file = find_file(name);

  auto library = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  library->load(file, ec, boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local);
  if (ec) throw PluginError("cannot load plugin " + file.string() + ": " + ec.message());
  for (const char* symbol : {"fibrodem_abi_version", "fibrodem_create_cell_model"})
    if (!library->has(symbol))
      throw PluginError("plugin " + file.string() + " has no entry point '" + symbol +
                        "' (define it with FIBRODEM_CELL_MODEL_PLUGIN)");
  const int abi = library->get<int()>("fibrodem_abi_version")();
  if (abi != kPluginAbiVersion)
    throw PluginError("plugin " + file.string() + " was built for plugin ABI " +
                      std::to_string(abi) + " but this fibrodem expects ABI " +
                      std::to_string(kPluginAbiVersion) + "; rebuild the plugin");

  CellModel* raw = library->get<CellModel*()>("fibrodem_create_cell_model")();
  if (raw == nullptr) throw PluginError("plugin " + file.string() + " created no model");
  // The deleter owns the library: it is unloaded only after the model is gone.
  std::shared_ptr<const CellModel> model(raw, [library](const CellModel* m) { delete m; });
  if (model->info().name != name)
    throw PluginError("plugin " + file.string() + " calls its model '" + model->info().name +
                      "', expected '" + name + "'");
  check_model_info(model->info(), file);

  records_[name] = PluginRecord{name, model->info().version, file, sha256_of_file(file)};
  models_[name] = model;
  return model;
}

const PluginRecord* PluginRegistry::record(const std::string& name) const {
  const auto it = records_.find(name);
  return it == records_.end() ? nullptr : &it->second;
}

// A model's metadata must be consistent before anything relies on it: names
// present and unique, bounds in order around the initial value, indices in range.
void check_model_info(const ModelInfo& info, const fs::path& file) {
  const std::string who = "plugin " + file.string() + " (model " + info.name + "): ";
  if (info.states.empty()) throw PluginError(who + "declares no states");
  auto check_names = [&](const auto& list, const char* what) {
    std::set<std::string> seen;
    for (std::size_t k = 0; k < list.size(); ++k) {
      if (list[k].name.empty()) throw PluginError(who + what + " " + std::to_string(k) + " has no name");
      if (!seen.insert(list[k].name).second) throw PluginError(who + "two " + what + "s are named '" + list[k].name + "'");
    }
  };
  check_names(info.states, "state");
  check_names(info.parameters, "parameter");
  check_names(info.inputs, "input");
  check_names(info.outputs, "output");
  for (const StateInfo& s : info.states) {
    if (!(s.lower <= s.upper))
      throw PluginError(who + "state '" + s.name + "' has its bounds reversed (lower " + std::to_string(s.lower) +
                        " > upper " + std::to_string(s.upper) + ")");
    if (!(s.initial >= s.lower && s.initial <= s.upper))
      throw PluginError(who + "state '" + s.name + "' starts at " + std::to_string(s.initial) +
                        ", outside its bounds [" + std::to_string(s.lower) + ", " + std::to_string(s.upper) + "]");
  }
  const auto n_states = static_cast<int>(info.states.size()), n_params = static_cast<int>(info.parameters.size());
  if (info.voltage_state >= n_states)
    throw PluginError(who + "voltage_state " + std::to_string(info.voltage_state) + " is not one of its " +
                      std::to_string(n_states) + " states");
  if (info.capacitance_parameter >= n_params)
    throw PluginError(who + "capacitance_parameter " + std::to_string(info.capacitance_parameter) +
                      " is not one of its " + std::to_string(n_params) + " parameters");
  if (info.capacitance_parameter >= 0 && !(info.parameters[info.capacitance_parameter].default_value > 0))
    throw PluginError(who + "its capacitance parameter '" + info.parameters[info.capacitance_parameter].name +
                      "' defaults to " + std::to_string(info.parameters[info.capacitance_parameter].default_value) +
                      ", expected > 0 pF");
}

std::vector<PluginRecord> PluginRegistry::loaded() const {
  std::vector<PluginRecord> out;
  for (const auto& [name, record] : records_) out.push_back(record);
  return out;
}

}  // namespace fibrodem
