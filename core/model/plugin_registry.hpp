// Finds cell-model plugins on a search path and loads them with Boost.DLL.
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
// around the initial value, an index out of range, a capacitance <= 0.
void check_model_info(const ModelInfo& info, const std::filesystem::path& file);

struct PluginRecord {
  std::string name;
  std::string version;
  std::filesystem::path file;
  std::string sha256;
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

  // Names of every plugin file found on the search path (not loaded).
  std::vector<std::string> available() const;

  // Provenance of each model loaded so far.
  std::vector<PluginRecord> loaded() const;
  // Provenance of the loaded model `name`, or null if it was not loaded.
  const PluginRecord* record(const std::string& name) const;

  const std::vector<std::filesystem::path>& search_path() const { return search_path_; }

 private:
  std::filesystem::path find_file(const std::string& name) const;

  std::vector<std::filesystem::path> search_path_;
  std::map<std::string, std::shared_ptr<const CellModel>> models_;
  std::map<std::string, PluginRecord> records_;
};

std::string sha256_of_file(const std::filesystem::path& file);

}  // namespace fibrodem
