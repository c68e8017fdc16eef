// Folders named in an environment variable, ':'-separated as PATH is
// (FIBRODEM_PLUGIN_PATH, FIBRODEM_MODULE_PATH): empty entries are skipped,
// an unset variable gives none.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace fibrodem {

inline std::vector<std::filesystem::path> directories_in_environment(const char* variable) {
  std::vector<std::filesystem::path> dirs;
  if (const char* value = std::getenv(variable)) {
    std::stringstream list(value);
    for (std::string dir; std::getline(list, dir, ':');)
      if (!dir.empty()) dirs.emplace_back(dir);
  }
  return dirs;
}

}  // namespace fibrodem
