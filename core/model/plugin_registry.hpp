// Finds plugins on a search path and loads them with Boost.DLL: cell models
// (`libfibrodem_<name>.so`, loaded here) and contact laws
// (`libfibrodem_contact_law_<name>.so`, through open(); mechanics/contact_law.hpp).
//
// Search path, in order: every directory of $FIBRODEM_PLUGIN_PATH (':'-separated),
// then `plugins/` next to the running executable and one level up (the build
// tree), then `../lib/fibrodem/plugins` (the install tree). A plugin file is
// `libfibrodem_<name>.so`. A loaded model keeps its library alive for as long as
// any shared_ptr to it lives (Chaste's DynamicCellModelLoader lesson).
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/cell_model.hpp"

namespace fibrodem {

class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws PluginError naming `file` and the fault if a model's metadata is
// inconsistent: no states, an empty or repeated name, bounds reversed or not
// around the initial value, an index out of range, a capacitance <= 0, a
// variant naming a parameter or state the model lacks or starting a state
// outside its bounds.
void check_model_info(const ModelInfo& info, const std::filesystem::path& file);
// The same rules, every fault found (empty: consistent), without throwing.
std::vector<std::string> model_info_problems(const ModelInfo& info);

// Loads one plugin file and creates its model, after checking its entry
// points, plugin ABI and C++ standard-library ABI (PluginError naming the file
// otherwise); its metadata is not checked (check_model_info).
std::shared_ptr<const CellModel> open_cell_model_file(const std::filesystem::path& file);

// The file of a contact-law plugin starts with this (after which comes its
// name); every other `libfibrodem_<name>.so` is a cell model.
inline constexpr const char* kContactLawFilePrefix = "libfibrodem_contact_law_";

// A plugin library, loaded and checked: its file, a handle that keeps it
// loaded while any copy lives, and the address of its factory function.
struct OpenedPlugin {
  std::filesystem::path file;
  std::shared_ptr<void> library;
  void (*factory)() = nullptr;  // cast to the kind's factory type
};

// Loads a plugin file of any kind and checks its entry points (the factory,
// its ABI version, the C++ standard-library ABI): PluginError naming the file
// and, for a missing entry point, `macro` as the way to define it.
OpenedPlugin open_plugin_file(const std::filesystem::path& file, const char* factory_symbol, const char* abi_symbol,
                              int abi_version, const char* macro);

struct PluginRecord {
  std::string name;
  std::string version;
  std::filesystem::path file;
  std::string sha256;
  // Plugins of the same name later on the search path, hidden by this one.
  std::vector<std::filesystem::path> shadowed;
};

class PluginRegistry {
 public:
  // $FIBRODEM_PLUGIN_PATH, then plugins/, ../plugins and ../lib/fibrodem/plugins
  // beside the running executable.
  static std::vector<std::filesystem::path> default_search_path();
  // The same, beside the executable in `exe_dir` (the Python module, which runs
  // inside python3, searches beside the build's `fibrodem`).
  static std::vector<std::filesystem::path> search_path_beside(const std::filesystem::path& exe_dir);

  explicit PluginRegistry(std::vector<std::filesystem::path> search_path = default_search_path());

  // Loads (once) and returns the model named `name`; throws PluginError naming
  // the search path and the models that were found if there is none.
  std::shared_ptr<const CellModel> load(const std::string& name);

  // Names of every cell-model plugin file found on the search path (not loaded).
  std::vector<std::string> available() const;
  // Names of the files `<file_prefix><name>.so` on the search path.
  std::vector<std::string> available(const std::string& file_prefix) const;

  // Finds `file_name` on the search path, loads it and checks that it exports
  // `factory_symbol` and that `abi_symbol` returns `abi_version` (else
  // PluginError naming the file, with `macro` as the way to define them).
  OpenedPlugin open(const std::string& file_name, const char* factory_symbol, const char* abi_symbol,
                    int abi_version, const char* macro) const;

  // Provenance of each model loaded so far.
  std::vector<PluginRecord> loaded() const;
  // Provenance of the loaded model `name`, or null if it was not loaded.
  const PluginRecord* record(const std::string& name) const;

  const std::vector<std::filesystem::path>& search_path() const { return search_path_; }

  // The file a model of this name loads from (the first on the search path);
  // throws PluginError as load() does if there is none.
  std::filesystem::path find_file(const std::string& name) const;

 private:
  std::filesystem::path find_file(const std::string& file_name, const std::string& what,
                                  const std::string& file_prefix) const;

  std::vector<std::filesystem::path> search_path_;
  std::map<std::string, std::shared_ptr<const CellModel>> models_;
  std::map<std::string, PluginRecord> records_;
};

std::string sha256_of_file(const std::filesystem::path& file);

}  // namespace fibrodem
