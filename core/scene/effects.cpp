#include "scene/effects.hpp"

#include <algorithm>

namespace fibrodem {

namespace {
// Effects whose processes this version of fibrodem has.
bool available(const std::string& effect) {
  return effect == "electrophysiology" || effect == "coupling";
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
      if (!available(effect))
        throw ManifestError(index_path("effects", i),
                            "the effect \"" + effect +
                                "\" is not available in this version of fibrodem (available: "
                                "electrophysiology, coupling)");
      if (!plan.has(effect)) plan.built.push_back({effect, "listed in the manifest's effects"});
    }
    if (plan.has("coupling") && !plan.has("electrophysiology"))
      plan.built.insert(plan.built.begin(),
                        {"electrophysiology", "coupling needs the cells' membrane potentials"});
    if (!plan.has("electrophysiology"))
      throw ManifestError("effects", "expected at least \"electrophysiology\": every output of "
                                     "this version of fibrodem needs it");
    if (!plan.has("coupling") && !tissue.cell_edges.empty())
      plan.notes.push_back("coupling not built: not in the listed effects, so the " +
                           std::to_string(tissue.cell_edges.size()) +
                           " cell-graph edges carry no current");
  } else {
    plan.built.push_back({"electrophysiology", "the scene records membrane potentials and biomarkers"});
    if (!tissue.cell_edges.empty())
      plan.built.push_back({"coupling", std::to_string(tissue.cell_edges.size()) +
                                            " cell pairs share gap junctions and their potentials "
                                            "are recorded"});
  }
  for (const auto& [type, spec] : scene.cells)
    if (!spec.myofilament.empty())
      plan.notes.push_back("myofilament model \"" + spec.myofilament + "\" of the " +
                           cell_type_name(type) + " not loaded: no effect needs contraction");
  return plan;
}

}  // namespace fibrodem
