// Which processes a scene needs (docs/dev/architecture.md#effects-and-processes:
// simulate only what the scene calls for). A manifest may list its
// `effects`; otherwise they follow from what it records. Each built process
// carries the reason it was built.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct Process {
  std::string name;  // an effect name: electrophysiology, coupling, ...
  std::string reason;
};

struct ProcessPlan {
  std::vector<Process> built;
  std::vector<std::string> notes;  // what was named but not built, and why
  bool has(const std::string& name) const;
};

// Throws ManifestError for a combination that cannot be built (e.g. contraction
// without a myofilament model).
ProcessPlan plan_processes(const Scene& scene, const Tissue& tissue);

// eps_xx, eps_yy, eps_xy: the tissue strain (traced when mechanics is built).
bool is_strain_variable(const std::string& variable);

}  // namespace fibrodem
