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
        path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace fibrodem
