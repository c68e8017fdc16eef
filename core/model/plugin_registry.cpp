#include "model/plugin_registry.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/directory_list.hpp"
#include "util/sha256.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <set>

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

// The file mapped, not read: its pages are those the loader mapped when it
// opened the plugin, where a read copied them into as many fresh pages.
std::string sha256_of_file(const fs::path& file) {
  const auto cannot = [&] { return PluginError("cannot read " + file.string() + " to hash it"); };
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw cannot();
  struct stat status {};
  if (::fstat(fd, &status) != 0) {
    ::close(fd);
    throw cannot();
  }
  const auto size = static_cast<std::size_t>(status.st_size);
  if (size == 0) {
    ::close(fd);
    return sha256_hex({});
  }
  void* bytes = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (bytes == MAP_FAILED) throw cannot();
  const std::string hex = sha256_hex(std::string_view(static_cast<const char*>(bytes), size));
  ::munmap(bytes, size);
  return hex;
}

std::vector<fs::path> PluginRegistry::default_search_path() {
  return search_path_beside(boost::dll::program_location().parent_path());
}

std::vector<fs::path> PluginRegistry::search_path_beside(const fs::path& exe_dir) {
  std::vector<fs::path> path = directories_in_environment("FIBRODEM_PLUGIN_PATH");
  path.push_back(exe_dir / "plugins");
  path.push_back(exe_dir.parent_path() / "plugins");
  path.push_back(exe_dir.parent_path() / "lib" / "fibrodem" / "plugins");
  return path;
}

PluginRegistry::PluginRegistry(std::vector<fs::path> search_path)
    : search_path_(std::move(search_path)) {}

std::vector<std::string> PluginRegistry::available() const {
  std::vector<std::string> names;
  for (const auto& name : available(kPrefix))
    if (("libfibrodem_" + name).rfind(kContactLawFilePrefix, 0) != 0) names.push_back(name);
  return names;
}

std::vector<std::string> PluginRegistry::available(const std::string& prefix) const {
  std::set<std::string> names;
  for (const auto& dir : search_path_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string file = entry.path().filename().string();
      if (file.rfind(prefix, 0) == 0 && file.size() > prefix.size() + 3 &&
          file.substr(file.size() - 3) == kSuffix)
        names.insert(file.substr(prefix.size(), file.size() - prefix.size() - 3));
    }
  }
  return {names.begin(), names.end()};
}

fs::path PluginRegistry::find_file(const std::string& file_name, const std::string& what,
                                   const std::string& file_prefix) const {
  for (const auto& dir : search_path_) {
    const fs::path candidate = dir / file_name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  std::string found;
  for (const auto& n : file_prefix == kPrefix ? available() : available(file_prefix))
    found += (found.empty() ? "" : ", ") + n;
  throw PluginError("no " + what + " (looked for " + file_name + " in: " + join_paths(search_path_) + "; " +
                    (file_prefix == kPrefix ? "models" : "contact laws") + " found: " +
                    (found.empty() ? "none" : found) + "; set FIBRODEM_PLUGIN_PATH to add a directory)");
}

OpenedPlugin open_plugin_file(const fs::path& file, const char* factory_symbol, const char* abi_symbol,
                              int abi_version, const char* macro) {
  auto library = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  library->load(file, ec, boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local);
  if (ec) throw PluginError("cannot load plugin " + file.string() + ": " + ec.message());
  for (const char* symbol : {abi_symbol, factory_symbol})
    if (!library->has(symbol))
      throw PluginError("plugin " + file.string() + " has no entry point '" + symbol + "' (define it with " + macro +
                        ")");
  const int abi = library->get<int()>(abi_symbol)();
  if (abi != abi_version)
    throw PluginError("plugin " + file.string() + " was built for plugin ABI " + std::to_string(abi) +
                      " but this fibrodem expects ABI " + std::to_string(abi_version) + "; rebuild the plugin");
  // The standard library's ABI before anything of the plugin's is read: a
  // mismatch makes every std::string in its metadata garbage.
  if (!library->has("fibrodem_stdlib_abi"))
    throw PluginError("plugin " + file.string() + " has no entry point 'fibrodem_stdlib_abi' (define it with " +
                      macro + ")");
  const std::string stdlib = library->get<const char*()>("fibrodem_stdlib_abi")();
  if (stdlib != kStdlibAbi)
    throw PluginError("plugin " + file.string() + " was built against the C++ standard library " + stdlib +
                      " but this fibrodem uses " + kStdlibAbi +
                      "; rebuild the plugin with the same standard library and ABI (the compiler fibrodem was "
                      "built with, and no -D_GLIBCXX_USE_CXX11_ABI or -stdlib option of its own)");
  auto* factory = reinterpret_cast<void (*)()>(&library->get<void*()>(factory_symbol));
  return OpenedPlugin{file, library, factory};
}

std::shared_ptr<const CellModel> open_cell_model_file(const fs::path& file) {
  const OpenedPlugin plugin = open_plugin_file(file, "fibrodem_create_cell_model", "fibrodem_abi_version",
                                               kPluginAbiVersion, "FIBRODEM_CELL_MODEL_PLUGIN");
  CellModel* raw = reinterpret_cast<CellModel* (*)()>(plugin.factory)();
  if (raw == nullptr) throw PluginError("plugin " + file.string() + " created no model");
  // The deleter owns the library: it is unloaded only after the model is gone.
  return std::shared_ptr<const CellModel>(raw, [library = plugin.library](const CellModel* m) { delete m; });
}

fs::path PluginRegistry::find_file(const std::string& name) const {
  return find_file(kPrefix + name + kSuffix, "cell-model plugin named '" + name + "'", kPrefix);
}

OpenedPlugin PluginRegistry::open(const std::string& file_name, const char* factory_symbol, const char* abi_symbol,
                                  int abi_version, const char* macro) const {
  const std::string prefix = file_name.rfind(kContactLawFilePrefix, 0) == 0 ? kContactLawFilePrefix : kPrefix;
  const std::string name = file_name.substr(prefix.size(), file_name.size() - prefix.size() - 3);
  const fs::path file = find_file(file_name,
                                  (prefix == kPrefix ? "cell-model plugin named '" : "contact law named '") + name + "'",
                                  prefix);
  return open_plugin_file(file, factory_symbol, abi_symbol, abi_version, macro);
}

std::shared_ptr<const CellModel> PluginRegistry::load(const std::string& name) {
  if (auto it = models_.find(name); it != models_.end()) return it->second;
  const fs::path file = find_file(name);
  std::shared_ptr<const CellModel> model = open_cell_model_file(file);
  if (model->info().name != name)
    throw PluginError("plugin " + file.string() + " calls its model '" + model->info().name +
                      "', expected '" + name + "'");
  check_model_info(model->info(), file);

  PluginRecord record{name, model->info().version, file, sha256_of_file(file), {}};
  // Files of the same name later on the search path: this one hides them.
  bool after = false;
  for (const auto& dir : search_path_) {
    const fs::path candidate = dir / (kPrefix + name + kSuffix);
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) continue;
    if (after && !fs::equivalent(candidate, file, ec)) record.shadowed.push_back(candidate);
    if (fs::equivalent(candidate, file, ec)) after = true;
  }
  records_[name] = record;
  models_[name] = model;
  return model;
}

const PluginRecord* PluginRegistry::record(const std::string& name) const {
  const auto it = records_.find(name);
  return it == records_.end() ? nullptr : &it->second;
}

std::vector<std::string> model_info_problems(const ModelInfo& info) {
  std::vector<std::string> problems;
  auto problem = [&](const std::string& what) { problems.push_back(what); };
  if (info.states.empty()) problem("declares no states");
  auto check_names = [&](const auto& list, const char* what) {
    std::set<std::string> seen;
    for (std::size_t k = 0; k < list.size(); ++k) {
      if (list[k].name.empty()) problem(std::string(what) + " " + std::to_string(k) + " has no name");
      else if (!seen.insert(list[k].name).second)
        problem(std::string("two ") + what + "s are named '" + list[k].name + "'");
    }
  };
  check_names(info.states, "state");
  check_names(info.parameters, "parameter");
  check_names(info.inputs, "input");
  check_names(info.outputs, "output");
  check_names(info.variants, "variant");
  for (const StateInfo& s : info.states) {
    if (!(s.lower <= s.upper))
      problem("state '" + s.name + "' has its bounds reversed (lower " + std::to_string(s.lower) + " > upper " +
              std::to_string(s.upper) + ")");
    else if (!(s.initial >= s.lower && s.initial <= s.upper))
      problem("state '" + s.name + "' starts at " + std::to_string(s.initial) + ", outside its bounds [" +
              std::to_string(s.lower) + ", " + std::to_string(s.upper) + "]");
  }
  const auto n_states = static_cast<int>(info.states.size()), n_params = static_cast<int>(info.parameters.size());
  if (info.voltage_state >= n_states)
    problem("voltage_state " + std::to_string(info.voltage_state) + " is not one of its " +
            std::to_string(n_states) + " states");
  const bool capacitance_known = info.capacitance_parameter >= 0 && info.capacitance_parameter < n_params;
  if (info.capacitance_parameter >= n_params)
    problem("capacitance_parameter " + std::to_string(info.capacitance_parameter) + " is not one of its " +
            std::to_string(n_params) + " parameters");
  if (capacitance_known && !(info.parameters[info.capacitance_parameter].default_value > 0))
    problem("its capacitance parameter '" + info.parameters[info.capacitance_parameter].name + "' defaults to " +
            std::to_string(info.parameters[info.capacitance_parameter].default_value) + ", expected > 0 pF");
  // A variant is checked whether or not a manifest selects it.
  for (const VariantInfo& v : info.variants) {
    for (const auto& [name, value] : v.parameters) {
      int k = -1;
      for (int i = 0; i < n_params; ++i)
        if (info.parameters[i].name == name) k = i;
      if (k < 0) problem("variant '" + v.name + "' sets parameter '" + name + "', which the model does not have");
      else if (k == info.capacitance_parameter && !(value > 0))
        problem("variant '" + v.name + "' sets the capacitance '" + name + "' to " + std::to_string(value) +
                ", expected > 0 pF");
    }
    for (const auto& [name, value] : v.initial_state) {
      const StateInfo* state = nullptr;
      for (const StateInfo& s : info.states)
        if (s.name == name) state = &s;
      if (!state) problem("variant '" + v.name + "' sets the initial value of state '" + name +
                          "', which the model does not have");
      else if (!(value >= state->lower && value <= state->upper))
        problem("variant '" + v.name + "' starts state '" + name + "' at " + std::to_string(value) +
                ", outside its bounds [" + std::to_string(state->lower) + ", " + std::to_string(state->upper) + "]");
    }
  }
  return problems;
}

// A model's metadata must be consistent before anything relies on it: names
// present and unique, bounds in order around the initial value, indices in
// range, variants naming what the model has.
void check_model_info(const ModelInfo& info, const fs::path& file) {
  const auto problems = model_info_problems(info);
  if (problems.empty()) return;
  std::string all = problems.front();
  if (problems.size() > 1) all += " (and " + std::to_string(problems.size() - 1) + " more: fibrodem check-plugin lists them)";
  throw PluginError("plugin " + file.string() + " (model " + info.name + "): " + all);
}

std::vector<PluginRecord> PluginRegistry::loaded() const {
  std::vector<PluginRecord> out;
  for (const auto& [name, record] : records_) out.push_back(record);
  return out;
}

}  // namespace fibrodem
