#include "model/plugin_probe.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace fibrodem::plugin_probe {

constexpr std::uint64_t kPoisonBits = 0x7ff8dead0000beefULL;
double poison() {
  double v;
  std::memcpy(&v, &kPoisonBits, sizeof v);
  return v;
}
bool is_poison(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return bits == kPoisonBits;
}
bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

std::vector<Setting> settings_of(const ModelInfo& info) {
  Setting base{"defaults", {}, {}};
  for (const auto& p : info.parameters) base.params.push_back(p.default_value);
  for (const auto& s : info.states) base.initial.push_back(s.initial);
  if (info.variants.empty()) return {base};
  std::vector<Setting> out;
  for (const VariantInfo& v : info.variants) {
    Setting s = base;
    s.label = "variant '" + v.name + "'";
    for (const auto& [name, value] : v.parameters)
      for (std::size_t k = 0; k < info.parameters.size(); ++k)
        if (info.parameters[k].name == name) s.params[k] = value;
    for (const auto& [name, value] : v.initial_state)
      for (std::size_t k = 0; k < info.states.size(); ++k)
        if (info.states[k].name == name) s.initial[k] = value;
    out.push_back(std::move(s));
  }
  return out;
}

double rest_input(const ModelInfo& info) { return info.kind == ModelKind::myofilament ? 1e-4 : 0.0; }

bool ionic(const ModelInfo& info) { return info.kind == ModelKind::ionic && info.voltage_state >= 0; }

double moved(const StateInfo& s, double value) {
  double next = s.gate ? (value < 0.5 ? value + 0.3 : value - 0.3) : (value != 0 ? 1.5 * value : 0.1);
  next = std::clamp(next, s.lower, s.upper);
  if (next == value) next = std::clamp(value != 0 ? 0.5 * value : -0.1, s.lower, s.upper);
  return next;
}

}  // namespace fibrodem::plugin_probe
