#include "mechanics/dem_spec.hpp"

#include <limits>

#include "mechanics/contact_law.hpp"
#include "model/plugin_registry.hpp"

namespace fibrodem {

const char* area_rule_name(AreaRule rule) {
  switch (rule) {
    case AreaRule::union_area: return "union";
    case AreaRule::capsule: return "capsule";
    case AreaRule::rectangle: return "rectangle";
  }
  return "?";
}

const char* length_mode_name(LengthMode mode) {
  return mode == LengthMode::spacing ? "spacing" : "total";
}

DemSpec read_dem_spec(JsonReader& r) {
  constexpr double big = std::numeric_limits<double>::max();
  DemSpec s;
  s.solver = r.text("solver", s.solver, {"dem"});
  s.contact_law = r.text("contact_law", s.contact_law);
  std::shared_ptr<const ContactLaw> law;
  try {
    law = load_contact_law(s.contact_law);
  } catch (const PluginError& e) {
    throw ManifestError(r.path_of("contact_law"), e.what());
  }
  const json& parameters = r.raw("contact_law_parameters");
  if (!parameters.is_null()) {
    const std::string path = r.path_of("contact_law_parameters");
    if (!parameters.is_object())
      throw ManifestError(path, "expected an object {name: value} of the law's parameters, got " +
                                    describe_json(parameters));
    JsonReader values(parameters, path);
    for (const auto& item : parameters.items())
      s.contact_law_parameters[item.key()] = values.number(item.key(), std::nullopt, -big, big);
  }
  s.kn_N_per_m = r.number("kn_N_per_m", s.kn_N_per_m, 1e-12, 1e12);
  s.ks_N_per_m = r.number("ks_N_per_m", s.ks_N_per_m, 0, 1e12);
  s.damping_ratio_normal = r.number("damping_ratio_normal", s.damping_ratio_normal, 0, 10);
  s.damping_ratio_shear = r.number("damping_ratio_shear", s.damping_ratio_shear, 0, 10);
  s.tensile_strength_N = r.number("tensile_strength_N", s.tensile_strength_N, 0, big);
  s.shear_strength_N = r.number("shear_strength_N", s.shear_strength_N, 0, big);
  s.friction = r.number("friction", s.friction, 0, 1e6);
  s.local_damping = r.number("local_damping", s.local_damping, 0, 1);
  s.fibroblast_stiffness_factor =
      r.number("fibroblast_stiffness_factor", s.fibroblast_stiffness_factor, 1e-6, 1e6);
  s.collagen_stiffness_factor = r.number("collagen_stiffness_factor", s.collagen_stiffness_factor, 1e-6, 1e6);
  s.bond_radius_multiplier = r.number("bond_radius_multiplier", s.bond_radius_multiplier, 0, 1e3);
  s.stiffness_inheritance =
      r.text("stiffness_inheritance", "contact", {"contact", "series"}) == "series"
          ? StiffnessInheritance::series
          : StiffnessInheritance::contact;
  s.density_kg_per_m3 = r.number("density_kg_per_m3", s.density_kg_per_m3, 1e-6, 1e9);
  s.safety_factor = r.number("safety_factor", s.safety_factor, 1e-3, 1.0);
  s.mass_scaling = r.number("mass_scaling", s.mass_scaling, 0, 1);
  s.multirate = r.boolean("multirate", s.multirate);
  s.skip_at_rest = r.boolean("skip_at_rest", s.skip_at_rest);
  s.dt_ms = r.number("dt_ms", s.dt_ms, 0, 1e3);
  const std::string rule = r.text("area_rule", "union", {"union", "capsule", "rectangle"});
  s.area_rule = rule == "capsule"     ? AreaRule::capsule
                : rule == "rectangle" ? AreaRule::rectangle
                                      : AreaRule::union_area;
  s.length_mode = r.text("length_mode", length_mode_name(s.length_mode), {"spacing", "total"}) == "total"
                      ? LengthMode::total
                      : LengthMode::spacing;
  s.fibroblasts_fixed = r.boolean("fibroblasts_fixed", s.fibroblasts_fixed);
  s.strain_bodies = r.text("strain_bodies", "particles", {"particles", "bodies"}) == "bodies"
                        ? StrainBodies::bodies
                        : StrainBodies::particles;
  s.contact_detection = r.boolean("contact_detection", s.contact_detection);
  s.contact_skin_um = r.number("contact_skin_um", s.contact_skin_um, 1e-3, 1e3);
  // Names the law does not declare are refused here, by path.
  for (const auto& [name, value] : s.contact_law_parameters) {
    try {
      DemSpec one = s;
      one.contact_law_parameters = {{name, value}};
      contact_law_parameter_values(law->info(), one);
    } catch (const std::invalid_argument& e) {
      throw ManifestError(join_path(r.path_of("contact_law_parameters"), name), e.what());
    }
  }
  return s;
}

}  // namespace fibrodem
