// Makes the population of one cell type from its manifest entry: loads the
// model, applies its variant and the parameter overrides, checks every name.
#pragma once

#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// Throws ManifestError (at the cell type's JSON path) for an unknown model,
// variant or parameter; PluginError for a plugin that breaks the contract.
Population make_population(CellType type, const CellTypeSpec& spec, PluginRegistry& registry);

}  // namespace fibrodem
