// `fibrodem check-plugin FILE|NAME`: the conformance checks of a cell-model
// plugin (core/model/plugin_check.hpp), each reported pass or fail with its
// faults. Exit 0 when every check passes, 3 (a plugin problem) otherwise.
#include <filesystem>
#include <iostream>

#include "apps/commands.hpp"
#include "model/plugin_check.hpp"
#include "model/plugin_registry.hpp"

namespace fibrodem::cli {

namespace {

// A path to a file (it exists, or it looks like one), else a model name.
std::filesystem::path plugin_file(const std::string& file_or_name) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(file_or_name, ec) || file_or_name.find('/') != std::string::npos ||
      file_or_name.ends_with(".so"))
    return file_or_name;
  return PluginRegistry().find_file(file_or_name);
}

}  // namespace

int check_plugin_command(const std::string& file_or_name) {
  return guarded([&] {
    const std::filesystem::path file = plugin_file(file_or_name);
    if (!std::filesystem::is_regular_file(file)) throw PluginError("no plugin file " + file.string());
    // Loaded without the loader's metadata check, so that every fault is listed.
    const auto model = open_cell_model_file(file);
    std::cout << "model " << model->info().name << " " << model->info().version << " (" << file.string() << ")\n";
    const PluginCheckReport report = check_plugin(*model);
    for (const PluginCheck& check : report.checks) {
      if (!check.skipped.empty()) {
        std::cout << "  skip  " << check.name << ": " << check.skipped << "\n";
        continue;
      }
      std::cout << (check.passed() ? "  PASS  " : "  FAIL  ") << check.name
                << (check.note.empty() ? "" : " (" + check.note + ")") << "\n";
      for (const auto& fault : check.faults) std::cout << "        - " << fault << "\n";
    }
    if (report.passed()) {
      std::cout << "all checks passed\n";
      return 0;
    }
    std::cout << report.failed_count() << " of " << report.checks.size() << " checks failed\n";
    return 3;
  });
}

}  // namespace fibrodem::cli
