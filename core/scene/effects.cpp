#include "scene/effects.hpp"

#include <algorithm>

namespace fibrodem {

bool is_strain_variable(const std::string& v) { return v == "eps_xx" || v == "eps_yy" || v == "eps_xy"; }

namespace {
bool any_myofilament(const Scene& scene) {
  for (const auto& [type, spec] : scene.cells)
    if (spec.myofilament) return true;
  return false;
}
}  // namespace

bool ProcessPlan::has(const std::string& name) const {
  return std::any_of(built.begin(), built.end(), [&](const Process& p) { return p.name == name; });
}

ProcessPlan plan_processes(const Scene& scene, const Tissue& tissue) {
  ProcessPlan plan;
  if (scene.effects_listed) {
    for (std::size_t i = 0; i < scene.effects.size(); ++i) {
      const std::string& effect = scene.effects[i];
      if (!plan.has(effect)) plan.built.push_back({effect, "listed in the manifest's effects"});
    }
    if (plan.has("mechano_electric_feedback") && scene.mechano_electric.stretch == StretchSource::tissue &&
        !plan.has("mechanics"))
      plan.built.push_back({"mechanics", "mechano_electric_feedback.stretch tissue reads the DEM tissue's deformation"});
    if (plan.has("mechanics") && !plan.has("contraction"))
      plan.built.push_back({"contraction", "mechanics needs the cells' lengths"});
    if (plan.has("mechano_electric_feedback") && !plan.has("contraction"))
      plan.built.push_back({"contraction", "mechano_electric_feedback needs the cells' stretch"});
    if (plan.has("contraction") && !any_myofilament(scene))
      throw ManifestError("effects", "contraction needs a myofilament model: set cells.myocyte.myofilament "
                                     "(for example \"rice\")");
    if ((plan.has("coupling") || plan.has("contraction")) && !plan.has("electrophysiology"))
      plan.built.insert(plan.built.begin(),
                        {"electrophysiology", "coupling and contraction need the cells' electrophysiology"});
    if (!plan.has("electrophysiology"))
      throw ManifestError("effects", "expected at least \"electrophysiology\": every output of "
                                     "this version of fibrodem needs it");
    if (!plan.has("coupling") && tissue.built_cell_edges() > 0)
      plan.notes.push_back("coupling not built: not in the listed effects, so the " +
                           std::to_string(tissue.built_cell_edges()) +
                           " cell-graph edges carry no current");
  } else {
    plan.built.push_back({"electrophysiology", "the scene records membrane potentials and biomarkers"});
    for (const auto& v : scene.output.traces.all_variables())
      if (is_strain_variable(v) && !plan.has("mechanics")) {
        plan.built.push_back({"mechanics", "output.traces records the tissue strain " + v});
        plan.built.push_back({"contraction", "mechanics needs the cells' lengths"});
      }
    if (scene.output.snapshots.strain && !plan.has("mechanics")) {
      plan.built.push_back({"mechanics", "output.snapshots.strain draws the cells' strain"});
      plan.built.push_back({"contraction", "mechanics needs the cells' lengths"});
    }
    if (tissue.built_cell_edges() > 0)
      plan.built.push_back({"coupling", std::to_string(tissue.built_cell_edges()) +
                                            " cell pairs share gap junctions and their potentials "
                                            "are recorded"});
  }
  if (scene.output.snapshots.strain && !plan.has("mechanics"))
    throw ManifestError("output.snapshots.strain", "draws the cells' strain, which needs the effect mechanics "
                                                   "(add \"mechanics\" to effects, or set strain false)");
  if (!plan.has("contraction"))
    for (const auto& [type, spec] : scene.cells) {
      if (spec.myofilament)
        plan.notes.push_back("myofilament model \"" + spec.myofilament->model + "\" of the " + cell_type_name(type) +
                             " not loaded: no effect needs contraction");
      if (spec.calcium_feedback)
        plan.notes.push_back(std::string("calcium_feedback of the ") + cell_type_name(type) +
                             " has no effect: contraction is not built");
    }
  return plan;
}

}  // namespace fibrodem
