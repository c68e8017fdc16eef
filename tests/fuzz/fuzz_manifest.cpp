// libFuzzer target: the manifest reader and command-line overrides.
// Every rejection must be a ManifestError naming
// the path (a clear error), never a crash, a hang, a leak or another
// exception. An input that is a JSON object is read as a manifest; any other
// input is read as lines of `--set` overrides (PATH=VALUE) applied to a small
// valid manifest, which takes the fuzzer deep into the reader at once.
//   scripts/fuzz.sh: builds it with clang and runs it, seeded with examples/*.json.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "util/manifest_error.hpp"
#include "fuzz_scene.hpp"
#include "scene/scene.hpp"

using fibrodem::fuzz::kCellPairManifest;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fibrodem::json manifest = fibrodem::json::parse(text, nullptr, /*allow_exceptions=*/false);
  try {
    if (manifest.is_discarded() || !manifest.is_object()) {
      manifest = fibrodem::json::parse(kCellPairManifest);
      std::istringstream lines(text);
      for (std::string line; std::getline(lines, line);) fibrodem::apply_override(manifest, line);
    }
    fibrodem::parse_scene(manifest);
  } catch (const fibrodem::ManifestError&) {
    // a clear rejection: fine
  }
  return 0;
}
