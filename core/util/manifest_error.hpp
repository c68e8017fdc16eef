#pragma once

#include <stdexcept>
#include <string>

namespace fibrodem {

// A problem with an experiment manifest: names the JSON path of the offending
// value (dotted, e.g. `stimulus[0].amplitude_pA`) and what was expected.
class ManifestError : public std::runtime_error {
 public:
  ManifestError(const std::string& path, const std::string& what)
      : std::runtime_error("manifest: " + (path.empty() ? std::string("(top level)") : path) +
                           ": " + what),
        path_(path), detail_(what) {}
  const std::string& path() const { return path_; }
  // What is wrong at the path, or what was expected there (what() without
  // "manifest: PATH: "), for an error re-thrown under a longer path.
  const std::string& detail() const { return detail_; }

 private:
  std::string path_, detail_;
};

}  // namespace fibrodem
