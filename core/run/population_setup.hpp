// Makes the population of one cell type from its manifest entry: loads the
// model, applies its variant and the parameter overrides, checks every name.
#pragma once

#include "model/plugin_registry.hpp"
#include "model/population.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// Throws ManifestError (at the model's JSON path) for an unknown model, variant
// or parameter, or a model of the wrong kind; PluginError for a plugin that
// breaks the contract.
// The population of one cell type run by spec's model: its variant's
// parameters and initial values, then the manifest's. Each manifest parameter
// that replaces a value the variant set adds a line to `warnings` (if given).
Population make_population(CellType type, const ModelSpec& spec, ModelKind kind, PluginRegistry& registry,
                           std::vector<std::string>* warnings = nullptr);

// Inputs an ionic model may read besides i_ext (which the core can supply).
inline constexpr const char* kTroponinFluxInput = "J_TRPN";

}  // namespace fibrodem
