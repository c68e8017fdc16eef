// The plugin registry of a run a study makes in this process, when the
// caller searches plugins elsewhere than `fibrodem run` does (the Python
// module runs inside python3, and searches beside the build's `fibrodem`).
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "model/plugin_registry.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// The scene's plugin_path, then `search`; null for an empty `search` (the
// Simulation then searches as `fibrodem run` does).
std::shared_ptr<PluginRegistry> registry_searching(const Scene& scene, const std::vector<std::filesystem::path>& search);

}  // namespace fibrodem
