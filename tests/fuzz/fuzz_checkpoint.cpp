// libFuzzer target: the checkpoint reader.
// An input is a checkpoint's payload (its fields); the target gives it a
// valid header and checksum, so that mutations reach the field parser and the
// loaders behind it (a file with a wrong checksum is refused before either,
// and the tests cover that), then resumes a small scene with contraction and
// DEM mechanics from it and runs it briefly. Every rejection must be a clear
// exception, never a crash, a hang or a leak.
//   scripts/fuzz.sh: builds and runs it; with FUZZ_CHECKPOINT_SEED=DIR set, the
//   target first writes the payload of a real checkpoint of its scene there.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "io/checkpoint_file.hpp"
#include "util/sha256.hpp"
#include "run/checkpoint_dir.hpp"
#include "run/simulation.hpp"
#include "scene/scene.hpp"

namespace {

const char* kScene = R"({
  "fibrodem": 1, "name": "fuzz_checkpoint", "duration_ms": 2,
  "effects": ["electrophysiology", "coupling", "contraction", "mechanics"],
  "tissue": {"builder": "strand", "type": "myocyte", "cells": 3},
  "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}},
  "stimulus": [{"target": [0], "start_ms": 0.5, "duration_ms": 1, "amplitude_pA": 4000}],
  "solver": {"method": "rush_larsen", "dt_ms": 0.05},
  "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 0.5}}
})";

// The header and checksum of checkpoint_file.cpp's layout around a payload.
std::string file_around(const std::string& payload) {
  std::string file = "FIBRODEM-CHECKPOINT\n";
  const std::uint32_t format = fibrodem::kCheckpointFormat;
  const std::uint64_t length = payload.size();
  file.append(reinterpret_cast<const char*>(&format), sizeof format);
  file.append(reinterpret_cast<const char*>(&length), sizeof length);
  file += payload;
  const auto digest = fibrodem::sha256(file);
  file.append(reinterpret_cast<const char*>(digest.data()), digest.size());
  return file;
}

std::shared_ptr<fibrodem::PluginRegistry> registry() {
  static auto shared = std::make_shared<fibrodem::PluginRegistry>();
  return shared;
}

// A real checkpoint's payload (after the 32-byte header, before the 32-byte digest).
void write_seed(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const fs::path run = fs::temp_directory_path() / "fibrodem_fuzz_checkpoint_seed";
  fs::remove_all(run);
  fibrodem::json manifest = fibrodem::json::parse(kScene);
  manifest["output"]["checkpoint"] = {{"every_ms", 1}};
  fibrodem::Scene scene = fibrodem::parse_scene(manifest);
  scene.output.dir = run.string();
  fibrodem::Simulation(scene, registry()).run();
  std::ifstream in(fibrodem::checkpoint_path(run, 1.0), std::ios::binary);
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fs::create_directories(dir);
  std::ofstream(dir / "checkpoint_payload.bin", std::ios::binary) << file.substr(32, file.size() - 64);
  fs::remove_all(run);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("FUZZ_CHECKPOINT_SEED")) write_seed(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string payload(reinterpret_cast<const char*>(data), size);
  fibrodem::CheckpointFields fields;
  try {
    fields = fibrodem::CheckpointFields::decode(file_around(payload));
  } catch (const fibrodem::CheckpointError&) {
    return 0;  // a clear rejection
  }
  fibrodem::Simulation simulation(fibrodem::parse_scene(fibrodem::json::parse(kScene)), registry());
  simulation.resume_from({"fuzz.ckpt", std::move(fields), {}});
  try {
    simulation.run();
  } catch (const std::runtime_error&) {
    // a checkpoint that does not fit, or a run that fails from its states: named, fine
  }
  return 0;
}
