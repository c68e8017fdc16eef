// A Scene is a validated experiment manifest (docs/reference/manifest.md):
// what to simulate and what to record, with every value checked and defaults
// filled in. Checks that need the plugins or the built tissue (model names,
// parameter names, stimulus targets) happen when a Simulation is set up.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coupling/coupling_spec.hpp"
#include "integrate/solver_spec.hpp"
#include "mechanics/dem_spec.hpp"
#include "mechanics/mechano_electric_spec.hpp"
#include "model/cell_type_spec.hpp"
#include "stimulus/stimulus_spec.hpp"
#include "util/json_reader.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {

inline constexpr int kManifestFormat = 1;

// One block of output.traces: these variables of these cells.
struct TraceBlock {
  std::vector<int> cells = {0};
  std::vector<std::string> variables = {"V"};
  std::string path = "output.traces";  // where it sits in the manifest, for errors
};

// output.traces: one object, or a list of blocks (so that variables of one
// cell type's model are traced beside another's) sharing one time axis.
struct TraceSpec {
  std::vector<TraceBlock> blocks = {TraceBlock{}};
  double every_ms = 0.1;
  double from_ms = 0;
  // Every variable of every block (repeats included).
  std::vector<std::string> all_variables() const {
    std::vector<std::string> all;
    for (const auto& b : blocks) all.insert(all.end(), b.variables.begin(), b.variables.end());
    return all;
  }
};

// Pictures (PNG) and ParaView files (VTK) of the tissue coloured by V, taken
// every every_ms from from_ms.
struct SnapshotSpec {
  double every_ms = 0;  // 0: none
  double from_ms = 0;
  bool png = true, vtk = true;
  bool strain = false;  // also strain_<t>_ms.png, the cells' fibre strain (needs mechanics)
};

// output.reentry: V of every cell sampled every every_ms from from_ms for
// phase singularities (phase_singularities.csv) and summary.json's
// "reentry" (measure/reentry.hpp, docs/topics/arrhythmia.md). Off unless given.
struct ReentrySpec {
  bool on = false;
  double every_ms = 1.0, from_ms = 0.0;
  double tau_ms = 10.0, V_star_mV = -50.0, link_mm = 1.0;
  double f_min_hz = 1.0, f_max_hz = 30.0;
  double clinical_f_min_hz = 3.0, clinical_f_max_hz = 12.0;
  double ps_density_bin_mm = 1.0;
};

// output.checkpoint: the run's whole state every every_ms, the newest `keep`
// kept (fibrodem resume DIR continues from the last).
struct CheckpointSpec {
  double every_ms = 0;  // 0: none
  int keep = 2;
};

struct OutputSpec {
  std::string dir;  // empty: write nothing (library use); the CLI sets a default
  bool overwrite = false;  // replace another run's files in dir (the CLI's --overwrite)
  TraceSpec traces;
  bool tissue_picture = false;  // tissue.png (by cell type) and tissue.vtk at the start
  bool maps = false;            // activation_map.png and maps.vtk (last beat) at the end
  // The ParaView files' format: "legacy" (ASCII .vtk) or "xml" (binary,
  // compressed .vtp, the snapshots listed in snapshots.pvd).
  std::string vtk_format = "legacy";
  bool report = true;           // report.html at the end (off: output.report false, --no-report)
  SnapshotSpec snapshots;
  double biomarkers_from_ms = 0;
  // output.biomarkers.rmp: "onset" (V at the beat's stimulus onset) or
  // "pre_upstroke" (mean V over rmp_window_ms ending rmp_gap_ms before the
  // cell's activation); output.biomarkers.cv: "fit" or "transit".
  std::string rmp_method = "onset";
  double rmp_window_ms = 5.0, rmp_gap_ms = 2.0;
  std::string cv_method = "fit";
  double progress_every_s = 1.0;
  CheckpointSpec checkpoint;
  ReentrySpec reentry;
};

// initial_state: the cells (and, with mechanics, the DEM bodies) start from
// another run's checkpoint of the same tissue and models, at this scene's t = 0.
struct InitialStateSpec {
  std::string from;     // a checkpoint file or a run's folder; empty: the models' own initial states
  double time_ms = -1;  // which of the folder's checkpoints (< 0: the latest)
};

// settle: before t = 0 the coupled tissue runs at rest (no stimulus, no
// mechanics) for ms; 0: not at all.
struct TissueSettleSpec {
  double ms = 0;
};

struct Scene {
  std::string name;
  std::uint64_t seed = 0;
  double duration_ms = 0;
  std::vector<std::string> effects;  // as listed; empty: derived from outputs
  bool effects_listed = false;
  std::shared_ptr<const TissueBuilder> tissue;
  std::map<CellType, CellTypeSpec> cells;
  CouplingSpec coupling;
  MechanoElectricSpec mechano_electric;
  DemSpec mechanics;  // Table 1 defaults; used when the effect mechanics is built
  std::vector<StimulusSpec> stimuli;
  SolverSpec solver;
  OutputSpec output;
  InitialStateSpec initial_state;
  TissueSettleSpec settle;
  // plugin_path: directories searched for plugins before $FIBRODEM_PLUGIN_PATH
  // and the bundled ones (each checked to exist).
  std::vector<std::string> plugin_path;
  json manifest;  // the manifest as resolved (after --set), for summary.json
};

inline const std::vector<std::string>& known_effects() {
  static const std::vector<std::string> effects = {
      "electrophysiology", "coupling", "contraction", "mechanics", "mechano_electric_feedback"};
  return effects;
}

// Validates a manifest; throws ManifestError naming the JSON path.
Scene parse_scene(const json& manifest);

// Reads a manifest file (ManifestError if missing or not JSON).
json read_manifest_file(const std::string& file);

// Applies one `PATH=VALUE` override (dotted path, [i] for list entries); VALUE
// is parsed as JSON if it is valid JSON, else taken as a string.
void apply_override(json& manifest, const std::string& assignment);

}  // namespace fibrodem
