#include "run/population_setup.hpp"

#include "io/csv_writer.hpp"

namespace fibrodem {

namespace {

template <class List>
std::string names_of(const List& list) {
  std::string s;
  for (const auto& item : list) s += (s.empty() ? "" : ", ") + item.name;
  return s.empty() ? "none" : s;
}

void check_ionic_contract(const ModelInfo& info) {
  if (info.voltage_state < 0 || info.voltage_state >= static_cast<int>(info.states.size()))
    throw PluginError("model " + info.name + " declares no membrane potential state");
  if (info.capacitance_parameter < 0 || info.capacitance_parameter >= static_cast<int>(info.parameters.size()))
    throw PluginError("model " + info.name + " declares no capacitance parameter");
  if (info.inputs.empty() || info.inputs[0].name != "i_ext")
    throw PluginError("model " + info.name + ": an ionic model's first input must be i_ext [pA]");
  for (std::size_t k = 1; k < info.inputs.size(); ++k)
    if (info.inputs[k].name != kTroponinFluxInput)
      throw PluginError("model " + info.name + " reads input " + info.inputs[k].name +
                        ", which fibrodem cannot supply (it supplies i_ext and " + kTroponinFluxInput + ")");
}

void check_myofilament_contract(const ModelInfo& info) {
  if (info.inputs.size() != 1 || info.inputs[0].name != "Ca_i")
    throw PluginError("model " + info.name + ": a myofilament model reads exactly one input, Ca_i [mM]");
  if (find_output(info, "sarcomere_length") < 0)
    throw PluginError("model " + info.name + ": a myofilament model must output sarcomere_length [um]");
}

}  // namespace

Population make_population(CellType type, const ModelSpec& spec, ModelKind kind, PluginRegistry& registry,
                           std::vector<std::string>* warnings) {
  Population pop;
  pop.type = type;
  try {
    pop.model = registry.load(spec.model);
    // The file's identity keys the lookup-table cache (model/voltage_table_cache.hpp).
    if (const PluginRecord* r = registry.record(spec.model))
      pop.model_origin = r->file.string() + " sha256:" + r->sha256;
  } catch (const PluginError& e) {
    throw ManifestError(join_path(spec.path, "model"), e.what());
  }
  const ModelInfo& info = pop.info();
  if (info.kind != kind)
    throw ManifestError(join_path(spec.path, "model"),
                        "model " + info.name + " is " + (info.kind == ModelKind::ionic ? "an ionic" : "a myofilament") +
                            " model; expected " + (kind == ModelKind::ionic ? "an ionic" : "a myofilament") + " model here");
  if (kind == ModelKind::ionic) check_ionic_contract(info);
  else check_myofilament_contract(info);

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
    if (warnings && variant && variant->parameters.count(name) && variant->parameters.at(name) != value)
      warnings->push_back(join_path(params_path, name) + " = " + format_number(value) + " replaces variant " +
                          variant->name + "'s value " + format_number(variant->parameters.at(name)) + " " +
                          info.parameters[static_cast<std::size_t>(k)].unit + " (model " + info.name + ")");
    pop.params[k] = value;
  }
  const std::string states_path = join_path(spec.path, "initial_state");
  for (const auto& [name, value] : spec.initial_state) {
    const int k = find_state(info, name);
    if (k < 0)
      throw ManifestError(join_path(states_path, name), "model " + info.name + " has no state \"" + name +
                                                             "\" (it has: " + names_of(info.states) + ")");
    const StateInfo& state = info.states[static_cast<std::size_t>(k)];
    if (!(value >= state.lower && value <= state.upper))
      throw ManifestError(join_path(states_path, name),
                          "expected a value within the state's range [" + format_number(state.lower) + ", " +
                              format_number(state.upper) + "] " + state.unit + ", got " + format_number(value));
    pop.initial_state[static_cast<std::size_t>(k)] = value;
  }
  pop.voltage_state = info.voltage_state;
  if (kind == ModelKind::myofilament) return pop;
  pop.capacitance_pF = pop.params[info.capacitance_parameter];
  if (!(pop.capacitance_pF > 0))
    throw ManifestError(join_path(params_path, info.parameters[info.capacitance_parameter].name),
                        "expected a capacitance > 0 pF, got " + std::to_string(pop.capacitance_pF));
  return pop;
}

}  // namespace fibrodem
