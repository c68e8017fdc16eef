// Simulation's state, private to core/run/. Its member functions are in the
// files of their concerns:
//   simulation.cpp              the run's life cycle (set-up order, run, steps)
//   simulation_assembly.cpp     the scene assembled: populations, coupling,
//                               myofilaments, mechanics, solver, threads
//   simulation_checkpoints.cpp  checkpoints written and a run resumed from one
//   simulation_outputs.cpp      output files, run.log, snapshots, progress
//   simulation_reentry.cpp      output.reentry's samples, kept and measured
//   simulation_settle.cpp       the coupled tissue settled at rest before t = 0
// and, on their own, mechanics_coupling.hpp (the cells driving the DEM) and
// state_guard.hpp (state limits and blow-up diagnosis).
#pragma once

#include <spdlog/spdlog.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coupling/gap_junction.hpp"
#include "integrate/cell_system.hpp"
#include "integrate/integrator.hpp"
#include "integrate/stability.hpp"
#include "io/background_writer.hpp"
#include "io/csv_writer.hpp"
#include "measure/reentry.hpp"
#include "run/checkpoint_dir.hpp"
#include "run/frame_log.hpp"
#include "run/halo_exchange.hpp"
#include "run/mechanics_coupling.hpp"
#include "run/mechanics_over_ranks.hpp"
#include "run/rank_layout.hpp"
#include "run/rank_reductions.hpp"
#include "run/resource_estimate.hpp"
#include "run/run_clock.hpp"
#include "run/simulation.hpp"
#include "run/strain_fields.hpp"
#include "run/trace_recorder.hpp"
#include "tissue/cell_partition.hpp"

namespace fibrodem {

// The parts of a run's state, each with its own concern; Simulation::Impl
// holds one of each.

// Where the wall time went (summary.json's timings) and when progress and
// the outputs were last reported.
struct RunTimes {
  std::chrono::steady_clock::time_point started, last_progress, last_flush;
  double measurement_s = 0, output_s = 0, integrator_s = 0, set_up_s = 0;
  double wall_s = 0;
};

// Checkpoints (output.checkpoint): their spacing (on the step grid of a
// fixed-step method), the checkpoint a resumed run starts from, the last
// one written and the one resumed from (summary.json).
struct CheckpointState {
  double every_ms = 0;
  std::optional<FoundCheckpoint> resume_point;
  json last, resumed_from;
  long long written = 0;
  // Fault injection for the tests of resume (FIBRODEM_TEST_KILL): SIGKILL at
  // this step, or halfway through writing this checkpoint (1 = the first).
  long long kill_at_step = -1, kill_in_checkpoint = -1;
};

// A resumed run's re-entry sampling as its checkpoint left it: the next
// sample's index (-1: a checkpoint of a build that kept no frames on disk)
// and the frames of V and of the fibre stretch in the logs beside it.
struct ReentryResume {
  long long next_sample = -1;
  std::size_t frames = 0, stretch_frames = 0;
};

// output.reentry: V of every cell at the sample times (interpolated between
// the ends of the step around each), V at the last step's end, and what was
// measured at the end (summary.json's "reentry").
struct ReentrySampling {
  VoltageFrames frames;
  std::vector<double> V_previous;
  long long next_sample = 0;  // index k of the next sample time from_ms + k every_ms
  json measured;
  // Every cell's V at a sample, interpolated (by tissue number). Split over
  // ranks: this rank's own cells' V at a sample, and on rank 0 every cell's
  // as gathered (rank order) and the frame; sized when the sampling starts.
  std::vector<double> own_V, gathered_V, frame_V;
  // With checkpoints, on the rank holding the frames: the frames on disk
  // beside them (run/frame_log.hpp), V's and, with mechanics, the stretch's.
  std::optional<FrameLog> V_log, stretch_log;
  ReentryResume resumed;  // what a resumed run's checkpoint holds of the sampling
};

// A run split over ranks (RunOptions::ranks with more than one; else
// `ranks` is null): this rank's cells and their ghosts (held under the
// numbers of CellSystem::numbering), the halo exchange of the ghosts'
// potentials, and where gathered values go (simulation_ranks.cpp).
struct RankSplit {
  std::shared_ptr<RankGroup> ranks;
  // The step control's error and stop, and at each step's end whether a
  // rank received SIGINT or SIGTERM, the same on every rank.
  std::shared_ptr<RankReductions> reductions;
  RankCells share;
  // A rank other than 0 that holds part of the cell graph
  // (build_part_of_graph): its cut, and where the coupling's regions and
  // map hold the whole graph's junctions. Empty otherwise.
  std::optional<PartialGraphCut> cut;
  std::optional<CouplingPlaces> coupling_places;
  std::unique_ptr<HaloExchange> halo;
  // Every rank's cells, rank after rank: where rank 0 places the values it
  // gathers (run/rank_layout.hpp).
  RankLayout layout;
};

struct Simulation::Impl : StepObserver {
  // ---- what is simulated ----
  Scene scene;
  RunOptions options;
  std::shared_ptr<PluginRegistry> registry;
  Tissue tissue;
  ProcessPlan plan;
  CellSystem system;
  std::unique_ptr<Integrator> integrator;  // null once the run is over
  std::string integrator_text, integrator_report;  // its describe() and report(), kept when it is freed
  std::string solver_choice;  // why solver.method "auto" chose what it did (empty: a method was named)
  StabilityEstimate stability;
  ResourceEstimate resources;
  std::unique_ptr<MechanicsCoupling> mechanics;  // split over ranks: every rank's (the DEM split), or rank 0's alone
  std::unique_ptr<MechanicsOverRanks> mechanics_over_ranks;  // split over ranks, the DEM on rank 0

  // ---- where it stands ----
  std::string status = "set up";
  std::string error;
  std::vector<std::string> warnings;  // found at set-up, logged when the run starts
  double start_ms = 0;        // 0, or the time of the checkpoint resumed from
  double t_reached_ms = 0;    // the end of the last step taken
  long long steps = 0;
  int interrupted_by = 0;     // the signal that stopped the run, if one did
  RunTimes times;

  // ---- what it writes ----
  std::shared_ptr<spdlog::logger> log;
  std::filesystem::path out;
  // Whether the run writes a folder (rank 0 does; the other ranks, which
  // write nothing but their parts of the checkpoints, still take part in
  // the gathers of what it writes), and the folder, known to every rank.
  bool writes_folder = false;
  std::filesystem::path run_folder;
  TraceRecorder traces;
  std::vector<BeatBiomarkers> beats;
  std::unique_ptr<BiomarkerTracker> tracker;
  CsvWriter biomarkers_csv;
  BackgroundWriter writer;  // the tissue picture and the snapshots
  long long snapshots_taken = 0;
  ReentrySampling reentry;
  // With mechanics, where an output asks for it: the cells' strain at the
  // snapshots and re-entry samples (run/strain_fields.hpp); else null.
  std::unique_ptr<StrainFields> strain_fields;
  CheckpointState checkpoints;

  RankSplit split;

  // ---- the life cycle (simulation.cpp) ----
  Impl(const Scene& s, std::shared_ptr<PluginRegistry> r, RunOptions o);
  void run();
  void advance_and_time_integrator();
  void advance_in_segments();
  void on_step_voltages(double t_old, double t_new, const double* V_new, std::size_t begin,
                        std::size_t end) override;
  void on_step(double t_old, double t_new, const double* dVdt) override;
  const MechanicsSolver* mechanics_solver() const { return mechanics ? &mechanics->solver() : nullptr; }
  json summary() const;
  void release_stepping_work();
  void release_run_buffers();

  // ---- the scene assembled (simulation_assembly.cpp) ----
  void make_logger();
  void choose_solver();
  void use_threads();
  void build_populations();
  const Population& population_of_type(CellType type) const;
  void settle(Population& pop, const CellTypeSpec& spec);
  std::map<int, CellType> types_of_traced_cells() const;
  void derive_contraction_from_traces();
  void build_myofilaments();
  void connect_stretch_activated_current();
  void connect_calcium_feedback(Population& host, Myofilament& m, const CellTypeSpec& spec);
  void warn_of_shadowed_plugins();
  void build_coupling();
  void build_mechanics();
  void build_lookup_tables();
  void start_from_initial_state();
  void settle_tissue();
  struct SettledRange {
    double V_min_mV = std::numeric_limits<double>::infinity(), V_max_mV = -V_min_mV, tail_change_mV = 0;
    long long unfinite_cell = -1;  // the first cell whose V is not finite, if any
    double unfinite_V_mV = 0;
  };
  SettledRange settled_range(const std::vector<double>& V_before_tail) const;  // (simulation_settle.cpp)
  void check_explicit_stability();
  void guard_resources();

  // ---- a run split over ranks (simulation_ranks.cpp) ----
  void split_over_ranks();
  Scene scene_of_own_traces() const;
  void refuse_traced_outputs() const;
  void connect_ranks();
  void build_tissue();
  void build_part_of_graph();
  std::string particles_kept_on_rank0_for() const;
  void release_particles_over_ranks();
  void release_cell_layout_over_ranks();
  std::unique_ptr<BiomarkerTracker> make_tracker();
  std::size_t tracked_edge(std::size_t cell_edge) const;
  std::vector<double> voltage_of_every_cell();
  void gather_from_ranks();
  void leave_failed_summary();

  // ---- checkpoints (simulation_checkpoints.cpp) ----
  void plan_checkpoints();
  CheckpointFields checkpoint_fields(double t);
  void write_checkpoint(double t);
  void resume();
  void restore(const CheckpointFields& f);
  void restore_beats(const CheckpointFields& f);
  void write_rank_checkpoint(const std::filesystem::path& file, const CheckpointFields& mine, bool kill);
  CheckpointFields recut_checkpoint(const std::filesystem::path& file, const CheckpointFields& checkpoint) const;
  std::vector<int> checkpoint_parts_of_own_cells(const CheckpointFields& checkpoint) const;

  // ---- output.reentry's samples (simulation_reentry.cpp) ----
  void start_reentry_sampling(double t);
  bool read_back_frames(std::size_t to_come);
  void keep_frames_on_disk();
  void save_reentry(CheckpointFields& f);
  void restore_reentry(const CheckpointFields& f);
  void sample_reentry_if_due(double t_old, double t_new);
  void add_reentry_frame_over_ranks(double t, const double* w);
  void measure_reentry();

  // ---- outputs and progress (simulation_outputs.cpp) ----
  void open_outputs();
  void open_biomarkers_csv();
  void log_setup();
  double next_sample_ms() const override;
  void on_sample(double t) override;
  void record_beat(const BeatBiomarkers& b);
  void write_biomarker_row(const BeatBiomarkers& b);
  void snapshot_if_due(double t);
  void write_file(std::function<void()> job);
  void reclaim_writer_core();
  void report_progress(std::chrono::steady_clock::time_point now, double t_new);
  void finish_writing();
  void log_run_end();
  void write_report_and_summary();
};

}  // namespace fibrodem
