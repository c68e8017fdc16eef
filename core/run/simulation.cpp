// The run's life cycle: the scene assembled in order, the run from its start
// (or a checkpoint) to its end, each step's observers, and how it ends.
#include "run/simulation.hpp"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "run/interrupt.hpp"
#include "run/output_dir.hpp"
#include "run/over_ranks.hpp"
#include "run/run_summary.hpp"
#include "run/simulation_impl.hpp"
#include "run/state_guard.hpp"
#include "run/tissue_snapshots.hpp"
#include "util/freed_heap.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

Simulation::Impl::Impl(const Scene& s, std::shared_ptr<PluginRegistry> r, RunOptions o)
    : scene(s), options(o), registry(std::move(r)) {
  ScopeTimer timer(times.set_up_s);
  if (options.ranks && options.ranks->size() > 1) split.ranks = options.ranks;
  run_folder = scene.output.dir;
  writes_folder = !run_folder.empty();
  if (split.ranks && split.ranks->rank() != 0) {  // rank 0 writes and tells
    scene.output.dir.clear();
    options.console_log = options.progress = false;
    options.on_progress = nullptr;
  }
  // Before any computation: a folder that cannot take the outputs stops here.
  if (!scene.output.dir.empty()) prepare_output_dir(scene.output.dir, scene.output.overwrite);
  if (!registry) {
    std::vector<fs::path> search(scene.plugin_path.begin(), scene.plugin_path.end());
    for (auto& dir : PluginRegistry::default_search_path()) search.push_back(std::move(dir));
    registry = std::make_shared<PluginRegistry>(std::move(search));
  } else if (!scene.plugin_path.empty()) {
    warnings.push_back("plugin_path ignored: this run was given its own plugin registry");
  }
  make_logger();
  build_tissue();
  plan = plan_processes(scene, tissue);
  choose_solver();
  if (!plan.has("mechanics")) release_particles_over_ranks();  // (the partition reads the cell graph only)
  split_over_ranks();
  use_threads();
  build_populations();
  derive_contraction_from_traces();
  build_myofilaments();
  warn_of_shadowed_plugins();
  if (!scene.solver.simd) {
    system.for_each_population([](Population& pop) { pop.scalar_reference = true; });
    plan.notes.push_back("solver.simd false: cell models evaluated one cell at a time in double");
  }
  build_coupling();
  connect_ranks();
  build_mechanics();
  if (plan.has("mechanics")) release_particles_over_ranks();
  system.stimulus = Stimulus(scene.stimuli, tissue);
  if (split.ranks) system.stimulus.hold_only(system.numbering);
  refuse_traced_outputs();
  traces = TraceRecorder(split.ranks ? scene_of_own_traces() : scene, system, mechanics != nullptr, plan.has("contraction"));
  build_lookup_tables();
  set_state_limits(system, scene.solver);
  start_from_initial_state();
  integrator = make_integrator(scene.solver);
  check_explicit_stability();
  plan_checkpoints();
  guard_resources();
}

void Simulation::Impl::run() {
  // The run frees its integrator and coupling at its end (release_run_buffers).
  if (status != "set up")
    throw std::logic_error("Simulation::run: this simulation has run already (status \"" + status +
                           "\"); make a new Simulation to run the scene again");
  times.started = times.last_progress = times.last_flush = std::chrono::steady_clock::now();
  status = "running";
  try {
    {
      ScopeTimer timer(times.output_s);
      open_outputs();
      log_setup();
    }
    tracker = make_tracker();
    if (!checkpoints.resume_point) settle_tissue();
    system.record_rest_lengths(mechanics != nullptr || mechanics_over_ranks != nullptr);
    if (checkpoints.resume_point) {
      resume();
    } else {
      system.gather_voltage();
      tracker->start(0.0, system.V_mV.data());
    }
    start_reentry_sampling(start_ms);
    release_cell_layout_over_ranks();
    // What the set-up freed (the tissue's build, the partition, the
    // coupling's assembly, the cell layout just freed) back to the system
    // before the stepping's arrays are made (27 MB on a rank of the
    // 846,279-cell sheet split 4 ways).
    give_freed_heap_back();
    try {
      advance_and_time_integrator();
    } catch (const InterruptedError& e) {
      status = "interrupted";
      error = e.what();
      interrupted_by = e.signal();
      log->warn("{}: stopping with every output written", error);
    }
    release_stepping_work();  // before the last beat's biomarkers are kept
    tracker->finish();
    gather_from_ranks();
    {
      ScopeTimer measuring(times.measurement_s);
      measure_reentry();
    }
    release_run_buffers();  // before the maps and the report are drawn
    ScopeTimer timer(times.output_s);
    if (!out.empty() && scene.output.maps) write_maps(out, scene.name, tissue, beats, scene.output.vtk_format);
    writer.finish();
    if (status == "running") status = "completed";
  } catch (const std::exception& e) {
    status = "failed";
    error = e.what();
    finish_writing();
  }
  if (options.progress) std::fprintf(stderr, "\n");
  times.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - times.started).count();
  try {
    traces.flush_csv();  // the last rows: a full disk shows here at the latest
  } catch (const std::exception& e) {
    if (status != "failed") status = "failed", error = e.what();
  }
  log_run_end();
  release_run_buffers();  // a failed run's too
  if (!out.empty()) {
    std::error_code ignored;
    // summary.json once at the end (with the report's time when there is
    // one); the copy open_outputs wrote stands for a run killed before.
    if (scene.output.report) {
      write_report_and_summary();
    } else {
      write_summary(out, summary());
      fs::remove(out / "report.html", ignored);  // an earlier run's, overwritten, would mislead
    }
    log->info("outputs in {}", fs::absolute(out).string());
  }
  if (status == "failed" && split.ranks && split.ranks->rank() != 0) leave_failed_summary();
  log->flush();
  if (status == "failed") throw std::runtime_error(error);
  if (status == "interrupted") throw InterruptedError(interrupted_by, error);
}

// The integrator (its work arrays) and the coupling (its matrix and CG
// vectors), freed as the stepping ends, and given back to the system: the
// last beat's biomarkers, a BeatBiomarkers a cell, and the beats rank 0
// gathers are then kept in their place rather than on top (rank 0 of the
// 846,279-cell sheet split 8 ways peaked at 300 MB with the freed heap
// kept, 245 MB without).
void Simulation::Impl::release_stepping_work() {
  if (!integrator) return;  // released before
  integrator_text = integrator->describe();
  integrator_report = integrator->report();
  integrator.reset();
  system.coupler.reset();
  give_freed_heap_back();
}

// What only the stepping needed, freed before the maps, summary.json and the
// report are written, so the run's peak memory is the stepping's, not theirs
// on top of it: the integrator and coupling (release_stepping_work), the
// biomarker tracker and the re-entry samples (measured by now). What
// Simulation's accessors give after run() stays: the tissue, the
// populations (summary's models), biomarkers, traces.
void Simulation::Impl::release_run_buffers() {
  if (!tracker && !integrator) return;  // released before (a run that completed, then its end)
  release_stepping_work();
  tracker.reset();
  reentry.frames = VoltageFrames();
  reentry.V_log.reset();
  reentry.stretch_log.reset();
  strain_fields.reset();
  std::vector<double>().swap(reentry.V_previous);
  std::vector<double>().swap(reentry.own_V);
  std::vector<double>().swap(reentry.gathered_V);
  std::vector<double>().swap(reentry.frame_V);
  give_freed_heap_back();  // the peak RSS is the stepping's
}

// The integrator's own time: its wall time less what the models, coupling,
// the observer (measurement, output, mechanics) took within it.
void Simulation::Impl::advance_and_time_integrator() {
  auto others = [&] {
    return system.seconds[0] + system.seconds[1] + system.seconds[2] + times.measurement_s + times.output_s +
           (mechanics ? mechanics->seconds() : 0.0);
  };
  const double before = others();
  const auto start = Clock::now();
  auto charge = [&] { times.integrator_s += std::max(0.0, seconds_since(start) - (others() - before)); };
  try {
    advance_in_segments();
  } catch (...) {
    charge();  // a failed run reports its time too
    throw;
  }
  charge();
}

// The run's stretch [start_ms, duration] cut at the checkpoint times; the
// integrator starts afresh at each (as at a stimulus edge), in a resumed
// run as in one never stopped.
void Simulation::Impl::advance_in_segments() {
  if (checkpoints.every_ms <= 0) return integrator->advance(system, start_ms, scene.duration_ms, *this);
  double t = start_ms;
  for (long long k = std::llround(start_ms / checkpoints.every_ms) + 1; t < scene.duration_ms - kTimeEpsilon_ms; ++k) {
    const double next = std::min(static_cast<double>(k) * checkpoints.every_ms, scene.duration_ms);
    integrator->advance(system, t, next, *this);
    t = next;
    write_checkpoint(t);
  }
}

// The biomarkers of most steps are measured on the step's threads. (The
// first thread's time here counts as measurement, not as ionic models.)
void Simulation::Impl::on_step_voltages(double t_old, double t_new, const double* V_new, std::size_t begin,
                                        std::size_t end) {
  if (!tracker->steps_by_range(t_new)) return;  // on_step measures the step whole
  const std::size_t first = tracked_edge(begin), last = tracked_edge(end);
  if (begin != 0) return tracker->step_cells(t_old, t_new, V_new, first, last);
  const auto start = Clock::now();
  tracker->step_cells(t_old, t_new, V_new, first, last);
  const double took_s = std::chrono::duration<double>(Clock::now() - start).count();
  times.measurement_s += took_s;
  system.seconds[CellSystem::kIonic] -= took_s;
}

void Simulation::Impl::on_step(double t_old, double t_new, const double* dVdt) {
  ++steps;
  if (steps == checkpoints.kill_at_step) std::raise(SIGKILL);
  t_reached_ms = t_new;
  // Few clock readings per step: a single cell steps in about a microsecond.
  const auto start = Clock::now();
  check_states(system, t_new, {scene.solver, stability, *registry, *integrator});
  if (!system.voltage_fresh) system.gather_voltage();
  if (!(system.voltages_observed && tracker->steps_by_range(t_new))) {  // else done in on_step_voltages
    tracker->step(t_old, t_new, system.V_mV.data(), dVdt);
  }
  sample_reentry_if_due(t_old, t_new);
  auto measured = Clock::now();
  times.measurement_s += std::chrono::duration<double>(measured - start).count();
  if (mechanics_over_ranks) {
    mechanics_over_ranks->advance(t_new, system, mechanics.get());  // (rank 0's mechanics times itself)
    measured = Clock::now();
  } else if (mechanics) {
    mechanics->advance(t_new, system);  // times itself
    measured = Clock::now();
  }
  if (strain_fields) strain_fields->complete(mechanics->solver());  // the re-entry samples' strain
  snapshot_if_due(t_new);
  reclaim_writer_core();
  if (measured - times.last_flush > std::chrono::seconds(1)) {
    traces.flush_csv();
    log->flush();
    times.last_flush = measured;
  }
  report_progress(measured, t_new);
  times.output_s += seconds_since(measured);
  // SIGINT / SIGTERM: stop here, at the end of a step (run() writes
  // everything). Split over ranks, every rank stops at the step at whose end
  // one of them has the signal (mpirun passes it to each at its own time).
  int signal = interrupt_signal();
  if (split.reductions) signal = static_cast<int>(split.reductions->largest(signal));
  if (signal) throw InterruptedError(signal, fmt::format("interrupted by {} at t = {} ms", signal_name(signal), t_new));
}

json Simulation::Impl::summary() const {
  return run_summary({.scene = scene,
                      .registry = *registry,
                      .plan = plan,
                      .warnings = warnings,
                      .integrator = integrator ? integrator->describe() : integrator_text,
                      .solver_choice = solver_choice,
                      .simulated_ms = t_reached_ms,
                      .status = status,
                      .error = split.ranks && status == "failed"
                                   ? fmt::format("rank {} of {}: {}", split.ranks->rank(), split.ranks->size(), error)
                                   : error,
                      .wall_s = times.wall_s,
                      .steps = steps,
                      .tissue = tissue,
                      .system = system,
                      .beats = beats,
                      .mechanics = mechanics != nullptr,
                      .peak_strain = mechanics ? mechanics->peak_strain() : std::array<double, 3>{0, 0, 0},
                      .mechanics_step_ms = mechanics ? mechanics->smallest_step_ms() : 0.0,
                      .mechanics_seconds = mechanics ? mechanics->seconds() : 0.0,
                      .measurement_seconds = times.measurement_s,
                      .output_seconds = times.output_s,
                      .integrator_seconds = times.integrator_s,
                      .set_up_seconds = times.set_up_s,
                      .last_checkpoint = checkpoints.last,
                      .resumed_from = checkpoints.resumed_from,
                      .trace_units = traces.units(),
                      .reentry = reentry.measured,
                      .mpi_ranks = split.ranks ? split.ranks->size() : 1});
}

Simulation::Simulation(const Scene& scene, std::shared_ptr<PluginRegistry> registry, RunOptions options)
    : impl_(std::make_unique<Impl>(scene, std::move(registry), options)) {}
Simulation::~Simulation() = default;

void Simulation::run() { impl_->run(); }
void Simulation::resume_from(FoundCheckpoint checkpoint) {
  impl_->checkpoints.resume_point = std::move(checkpoint);
}
const Tissue& Simulation::tissue() const { return impl_->tissue; }
const ProcessPlan& Simulation::processes() const { return impl_->plan; }
const std::vector<BeatBiomarkers>& Simulation::biomarkers() const { return impl_->beats; }
const std::vector<double>& Simulation::trace_times() const { return impl_->traces.times(); }
json Simulation::summary() const { return impl_->summary(); }
std::string Simulation::integrator_description() const {
  return impl_->integrator ? impl_->integrator->describe() : impl_->integrator_text;
}

std::string Simulation::resource_estimate() const { return impl_->resources.describe(); }

std::vector<std::string> Simulation::trace_column_names() const { return impl_->traces.column_names(); }
const std::vector<std::vector<double>>& Simulation::trace_samples() const { return impl_->traces.samples(); }

const std::vector<double>& Simulation::trace(const std::string& variable, int cell) const {
  return impl_->traces.trace(variable, cell);
}

}  // namespace fibrodem
