#include "study/plugin_search.hpp"

namespace fibrodem {

std::shared_ptr<PluginRegistry> registry_searching(const Scene& scene,
                                                   const std::vector<std::filesystem::path>& search) {
  if (search.empty()) return nullptr;
  std::vector<std::filesystem::path> path(scene.plugin_path.begin(), scene.plugin_path.end());
  path.insert(path.end(), search.begin(), search.end());
  return std::make_shared<PluginRegistry>(std::move(path));
}

}  // namespace fibrodem
