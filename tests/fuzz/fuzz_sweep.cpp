// libFuzzer target: the sweep file reader:
// the sweep object, its `set` and `grid`, and every point's manifest as the
// sweep would run it, read into a scene. Every rejection must be a
// ManifestError naming the path, never a crash, a hang, a leak or another
// exception. The manifest a sweep names is always a small valid one.
//   scripts/fuzz.sh: builds it with clang and runs it, seeded with examples/*sweep*.json.
#include <cstddef>
#include <cstdint>
#include <string>

#include "util/manifest_error.hpp"
#include "fuzz_scene.hpp"
#include "scene/scene.hpp"
#include "scene/sweep_file.hpp"

namespace {
using fibrodem::fuzz::kCellPairManifest;
constexpr std::size_t kPointsRead = 64;  // each point's manifest read into a scene (the rest only expanded)
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const fibrodem::json sweep = fibrodem::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (sweep.is_discarded()) return 0;
  try {
    const fibrodem::SweepFile file =
        fibrodem::read_sweep(sweep, [](const std::string&) { return fibrodem::json::parse(kCellPairManifest); });
    for (std::size_t k = 0; k < file.points.size() && k < kPointsRead; ++k)
      fibrodem::parse_scene(fibrodem::point_manifest(file, file.points[k]));
  } catch (const fibrodem::ManifestError&) {
    // a clear rejection: fine
  }
  return 0;
}
