// summary.json: what a run was (manifest, plugins, processes, integrator), how
// it went (status, steps, wall time) and what it measured (mean biomarkers,
// conduction velocity, peak strain). Written whole or not at all.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "integrate/cell_system.hpp"
#include "measure/biomarkers.hpp"
#include "model/plugin_registry.hpp"
#include "scene/effects.hpp"
#include "util/json_reader.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Per cell type with beats, the mean of each biomarker over the beats where
// the cell fired and the biomarker is finite (null where it never is), the
// number of beats where it fired (beats_measured) and where it did not
// (beats_not_fired).
json mean_biomarkers(const std::vector<BeatBiomarkers>& beats);

// Conduction velocity of each beat along the fibre (y), fitted over the
// unstimulated cells that carried the wave (measure/biomarkers.hpp: fired,
// with a myocyte's 20 mV rise).
// method: "fit" (least squares) or "transit" (end to end), output.biomarkers.cv.
json conduction(const Tissue& tissue, const Stimulus& stimulus, const std::vector<BeatBiomarkers>& beats,
                const std::string& method = "fit");

// What summary.json reports, as the simulation holds it.
struct RunFacts {
  const Scene& scene;
  const PluginRegistry& registry;
  const ProcessPlan& plan;
  const std::vector<std::string>& warnings;  // found at set-up
  std::string integrator;                    // Integrator::describe()
  std::string solver_choice;                 // solver.method "auto": what it chose and why (else empty)
  double simulated_ms = 0;                   // how far the run got (the end of its last step)
  const std::string& status;                 // set up | running | completed | failed | interrupted
  const std::string& error;                  // empty unless failed
  double wall_s;
  long long steps;
  const Tissue& tissue;
  const CellSystem& system;                  // its stimulus and wall time per part
  const std::vector<BeatBiomarkers>& beats;
  bool mechanics;                            // the three below only mean something with it
  std::array<double, 3> peak_strain;
  double mechanics_step_ms;                  // the smallest step taken
  double mechanics_seconds;
  // Wall time [s] of the run's own work around the models: biomarkers and
  // state checks (measurement), traces, pictures and files (output), the
  // integrator's own arithmetic (CVODE's Newton and linear solves, the loop),
  // and building the scene before the run (set_up, not part of wall_s).
  double measurement_seconds = 0, output_seconds = 0, integrator_seconds = 0, set_up_seconds = 0;
  // output.checkpoint: the last written ({file, time_ms}), and the one a
  // resumed run started from (null when none).
  json last_checkpoint = nullptr, resumed_from = nullptr;
  json trace_units = json::object();  // traced variable -> unit (TraceRecorder::units)
  json reentry = nullptr;             // output.reentry's measurements (measure/reentry.hpp), or null
  int mpi_ranks = 1;                  // the ranks the tissue was split over (docs/guide/parallel.md)
};

json run_summary(const RunFacts& facts);

// Per cell type, the model, variant and every parameter value the run used
// (defaults, variant, manifest and what the set-up changed, e.g. calcium
// feedback's troponin_buffer_scale), with its myofilament model's under
// "myofilament": summary.json's "models".
json models_used(const CellSystem& system);

// Writes dir/summary.json through a temporary file and a rename.
void write_summary(const std::filesystem::path& dir, const json& summary);

}  // namespace fibrodem
