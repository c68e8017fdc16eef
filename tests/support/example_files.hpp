// The example manifests the schema tests check (examples/, examples/paper,
// examples/arrhythmia), sorted.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

namespace fibrodem::testing {

inline std::vector<std::filesystem::path> example_files() {
  const std::filesystem::path source = FIBRODEM_SOURCE_DIR;
  std::vector<std::filesystem::path> files;
  for (const auto& folder : {source / "examples", source / "examples" / "paper", source / "examples" / "arrhythmia"})
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace fibrodem::testing
