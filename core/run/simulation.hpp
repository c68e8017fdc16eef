// A Simulation sets up a scene (tissue, populations, coupling, stimulus,
// integrator, observers: everything the scene's effects call for and nothing
// else), runs it, and writes the output directory as it goes:
//   summary.json, biomarkers.csv, traces.csv, run.log   (docs/reference/outputs.md)
// Setting up checks what only the plugins and the built tissue can tell (model,
// variant and parameter names, stimulus targets, traced variables) and throws
// ManifestError naming the JSON path.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "measure/biomarkers.hpp"
#include "model/plugin_registry.hpp"
#include "run/checkpoint_dir.hpp"
#include "util/rank_group.hpp"
#include "scene/effects.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// The run stopped because a state left its physical range or became NaN/Inf.
class BlowUpError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RunOptions {
  bool console_log = false;  // also log to stderr
  bool progress = false;     // progress line on a terminal
  // Called with the simulated time [ms] every output.progress_every_s of wall
  // time, at the end of a step, on the thread running the simulation (the
  // Python module's progress callback). An exception from it fails the run.
  std::function<void(double t_ms)> on_progress;
  // The ranks the tissue is split over (docs/guide/parallel.md; null or one rank:
  // this process runs it all). Every rank makes a Simulation of the same
  // scene; rank 0 writes the output folder, the others nothing.
  std::shared_ptr<RankGroup> ranks;
};

class Simulation {
 public:
  explicit Simulation(const Scene& scene, std::shared_ptr<PluginRegistry> registry = nullptr,
                      RunOptions options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Runs to the scene's duration. On failure the output written so far stays,
  // summary.json says what failed, and the error is rethrown.
  void run();
  // Makes run() continue from a checkpoint of this scene written into its
  // output folder (fibrodem resume): states, trackers, traces and files are
  // taken back to the checkpoint's time. Call before run(). A checkpoint
  // written over another number of MPI ranks than this run's (one process:
  // 1) is refused here, with CheckpointError naming both counts.
  void resume_from(FoundCheckpoint checkpoint);

  const Tissue& tissue() const;
  const ProcessPlan& processes() const;
  const std::vector<BeatBiomarkers>& biomarkers() const;
  const std::vector<double>& trace_times() const;
  // Samples of a traced variable of a cell; throws if it was not traced.
  const std::vector<double>& trace(const std::string& variable, int cell) const;
  // Every traced column's name (VAR_CELL, as in traces.csv) and samples.
  std::vector<std::string> trace_column_names() const;
  const std::vector<std::vector<double>>& trace_samples() const;
  json summary() const;
  std::string integrator_description() const;
  // Memory and output size the scene was estimated to need (checked at set-up).
  std::string resource_estimate() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fibrodem
