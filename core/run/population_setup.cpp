#include "run/population_setup.hpp"

namespace fibrodem {

namespace {

template <class List>
std::string names_of(const List& list) {
  std::string s;
  for (const auto& item : list) s += (s.empty() ? "" : ", ") + item.name;
  return s.empty() ? "none" : s;
}

void check_contract(const ModelInfo& info) {
  if (info.kind != ModelKind::ionic)
    throw PluginError("model " + info.name + " is a myofilament model; a cell type's \"model\" must be ionic");
  if (info.voltage_state < 0 || info.voltage_state >= static_cast<int>(info.states.size()))
    throw PluginError("model " + info.name + " declares no membrane potential state");
  if (info.capacitance_parameter < 0 || info.capacitance_parameter >= static_cast<int>(info.parameters.size()))
    throw PluginError("model " + info.name + " declares no capacitance parameter");
  if (info.inputs.empty() || info.inputs[0].name != "i_ext")
    throw PluginError("model " + info.name + ": an ionic model's first input must be i_ext [pA]");
  if (info.inputs.size() > 1)
    throw PluginError("model " + info.name + " reads inputs (" + names_of(info.inputs) +
                      ") that this version of fibrodem cannot supply beyond i_ext");
}

}  // namespace

Population make_population(CellType type, const CellTypeSpec& spec, PluginRegistry& registry) {
  Population pop;
  pop.type = type;
  try {
    pop.model = registry.load(spec.model);
  } catch (const PluginError& e) {
    throw ManifestError(join_path(spec.path, "model"), e.what());
  }
  const ModelInfo& info = pop.info();
  check_contract(info);

  for (const auto& p : info.parameters) pop.params.push_back(p.default_value);
  for (const auto& s : info.states) pop.initial_state.push_back(s.initial);

  const VariantInfo* variant = nullptr;
  if (!spec.variant.empty()) {
    for (const auto& v : info.variants)
      if (v.name == spec.variant) variant = &v;
    if (!variant)
      throw ManifestError(join_path(spec.path, "variant"),
                          "model " + info.name + " has no variant \"" + spec.variant +
                              "\" (it has: " + names_of(info.variants) + ")");
  } else if (!info.variants.empty()) {
    variant = &info.variants.front();
  }
  if (variant) {
    pop.variant = variant->name;
    for (const auto& [name, value] : variant->parameters) {
      const int k = find_parameter(info, name);
      if (k < 0) throw PluginError("model " + info.name + ", variant " + variant->name + ": unknown parameter " + name);
      pop.params[k] = value;
    }
    for (const auto& [name, value] : variant->initial_state) {
      const int k = find_state(info, name);
      if (k < 0) throw PluginError("model " + info.name + ", variant " + variant->name + ": unknown state " + name);
      pop.initial_state[k] = value;
    }
  }

  const std::string params_path = join_path(spec.path, "parameters");
  for (const auto& [name, value] : spec.parameters) {
    const int k = find_parameter(info, name);
    if (k < 0)
      throw ManifestError(join_path(params_path, name),
                          "model " + info.name + " has no parameter \"" + name + "\" (it has: " +
                              names_of(info.parameters) + ")");
    pop.params[k] = value;
  }
  pop.voltage_state = info.voltage_state;
  pop.capacitance_pF = pop.params[info.capacitance_parameter];
  if (!(pop.capacitance_pF > 0))
    throw ManifestError(join_path(params_path, info.parameters[info.capacitance_parameter].name),
                        "expected a capacitance > 0 pF, got " + std::to_string(pop.capacitance_pF));
  return pop;
}

}  // namespace fibrodem
