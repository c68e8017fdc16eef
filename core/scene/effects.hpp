// Which processes a scene needs (DESIGN.md: "simulate only what the scene
// calls for"). A manifest may list its `effects`; otherwise they follow from
// what it records. Each built process carries the reason it was built.
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

// Throws ManifestError for an effect this build cannot simulate yet.
ProcessPlan plan_processes(const Scene& scene, const Tissue& tissue);

}  // namespace fibrodem
