// A cell model's metadata as JSON: what `fibrodem plugins --json` prints and
// what the Python module's fibrodem.plugins() returns (one description, so the
// two cannot disagree).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/cell_model.hpp"
#include "model/plugin_registry.hpp"

namespace fibrodem {

// name, version, description, reference, file, sha256, kind; states (name,
// unit, initial, lower, upper, gate), parameters (name, unit, default,
// description), inputs and outputs (name, unit), variants (name, description,
// the parameters and initial states they set).
nlohmann::json describe_model(const ModelInfo& info, const PluginRecord& record);
// Declared parameters (name, unit, default, description), a model's or a contact law's.
nlohmann::json describe_parameters(const std::vector<ParameterInfo>& parameters);

// Every model on the registry's search path, described; a plugin that cannot be
// loaded is left out and its error appended to `errors`.
nlohmann::json describe_available_models(PluginRegistry& registry, std::vector<std::string>& errors);

}  // namespace fibrodem
