// The run's outputs (docs/reference/outputs.md): the output folder's
// files opened (or continued, after a checkpoint), run.log, trace samples,
// biomarkers.csv, pictures and snapshots on the writer's thread, the progress
// line, and the report (output.reentry's samples: simulation_reentry.cpp).
#include <omp.h>
#include <spdlog/sinks/basic_file_sink.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/tissue_imprint.hpp"
#include "report/run_report.hpp"
#include "run/checkpoint_dir.hpp"
#include "run/run_summary.hpp"
#include "run/simulation_impl.hpp"
#include "run/tissue_snapshots.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

// biomarkers.csv with its header alone.
void Simulation::Impl::open_biomarkers_csv() {
  biomarkers_csv = CsvWriter(out / "biomarkers.csv", {"cell", "type", "beat", "activation_ms", "rmp_mV", "apo_mV",
                                                      "apd90_ms", "dvdt_max_mV_per_ms", "apd50_ms"});
}

// A resumed run appends to run.log and continues traces.csv and
// biomarkers.csv from the checkpoint's lengths (restore()).
void Simulation::Impl::open_outputs() {
  if (scene.output.dir.empty()) return;
  out = scene.output.dir;
  fs::create_directories(out);
  auto file_sink =
      std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "run.log").string(), !checkpoints.resume_point);
  file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
  log->sinks().push_back(file_sink);
  if (!checkpoints.resume_point) {
    clear_checkpoints(out);  // an earlier run's, in a folder given --overwrite
    fs::remove(out / kSnapshotCollection);  // likewise: this run lists its own snapshots
    if (!split.ranks) traces.open_csv(out / "traces.csv");  // split over ranks: written whole at the end
    open_biomarkers_csv();
    // (The tissue stays as built: the writer may draw it while the run starts.)
    if (scene.output.tissue_picture) write_file([this] { write_tissue_overview(out, scene.name, tissue, scene.output.vtk_format); });
  }
  write_summary(out, summary());
}

void Simulation::Impl::log_setup() {
  // (Rank 0 of a split run may hold the particles' imprint instead: io/tissue_imprint.hpp.)
  const std::size_t particles = tissue.imprint() ? tissue.imprint()->cells.particles() : tissue.particles.size();
  log->info("scene '{}': {} cells ({} myocytes, {} fibroblasts), {} particles, {} cell-graph edges",
            scene.name, tissue.cell_count(), tissue.count(CellType::myocyte),
            tissue.count(CellType::fibroblast), particles, tissue.built_cell_edges());
  for (const auto& p : plan.built) log->info("process built: {} ({})", p.name, p.reason);
  for (const auto& note : plan.notes) log->info("{}", note);
  system.for_each_population([&](const Population& pop) {
    log->info("{}: {} model {} {}{}, {} cells x {} states", cell_type_name(pop.type),
              pop.info().kind == ModelKind::ionic ? "ionic" : "myofilament", pop.info().name, pop.info().version,
              pop.variant.empty() ? "" : ", variant " + pop.variant, pop.size(), pop.n_states());
    // What the model says of itself (an imported model: how its V and stimulus were found).
    if (!pop.info().description.empty())
      log->info("{}: model {}: {}", cell_type_name(pop.type), pop.info().name, pop.info().description);
  });
  if (mechanics)
    log->info("mechanics: DEM, contact law {}, step {:.4g} ms (stable {:.4g} ms), subcycled against the "
              "cells' steps", scene.mechanics.contact_law, mechanics->smallest_step_ms(),
              mechanics->solver().stable_step_ms());
  if (system.sac.on)
    log->info("stretch-activated current: G = {} nS, E = {} mV, lambda_max = {}, lambda: {}", system.sac.G_nS,
              system.sac.E_mV, system.sac.lambda_max,
              system.sac.tissue_stretch ? "each cell's fibre stretch in the DEM tissue, at the end of each cell step"
                                        : "SL / SL_rest of each cell's myofilament model");
  if (system.coupler)
    log->info("coupling: gap junctions, D_m = {} nS{}, D_f = {} nS{}{}, {}", scene.coupling.D_m_nS,
              scene.coupling.D_m_side_nS == scene.coupling.D_m_nS
                  ? std::string()
                  : fmt::format(" end to end and {} nS side to side", scene.coupling.D_m_side_nS),
              scene.coupling.D_f_nS,
              scene.coupling.regions.empty()
                  ? std::string()
                  : fmt::format(" ({} regions of their own, coupling.regions)", scene.coupling.regions.size()),
              scene.coupling.field ? fmt::format(", times a map of {} x {} samples (coupling.field)", scene.coupling.field->rows,
                                                 scene.coupling.field->columns)
                                   : std::string(),
              !scene.solver.fixed_step()     ? std::string("in the integrator's implicit solve")
              : system.implicit_coupling     ? fmt::format("backward Euler (split), every {} cell step(s)",
                                                           system.coupling_every)
                                             : fmt::format("explicit, updated every {} cell step(s)",
                                                           system.coupling_every));
  log->info("integrator: {}; {} threads", integrator->describe(), system.thread_governor().chosen());
  for (const auto& w : warnings) log->warn("{}", w);
}

double Simulation::Impl::next_sample_ms() const { return traces.next_sample_ms(); }

void Simulation::Impl::on_sample(double t) {
  ScopeTimer timer(times.output_s);
  traces.sample(t, system, mechanics_solver());
}

// Split over ranks: this rank's cells' beats (the tracker's, make_tracker),
// gathered and written at the end (gather_from_ranks).
void Simulation::Impl::record_beat(const BeatBiomarkers& b) {
  if (split.ranks) {
    beats.push_back(b);
    return;
  }
  // Room for a beat of every cell at every onset at once: grown by doubling,
  // the list would hold up to twice that, and three times while it moves.
  if (beats.size() == beats.capacity()) {
    const std::size_t onsets = std::max<std::size_t>(1, system.stimulus.onsets(scene.duration_ms).size());
    const std::size_t expected = onsets * system.cell_count();
    if (beats.size() < expected) beats.reserve(expected);
  }
  beats.push_back(b);
  write_biomarker_row(b);
}

void Simulation::Impl::write_biomarker_row(const BeatBiomarkers& b) {
  if (!biomarkers_csv.is_open()) return;
  biomarkers_csv.cell(static_cast<long long>(b.cell))
      .cell(std::string(cell_type_name(b.type)))
      .cell(static_cast<long long>(b.beat));
  if (fired(b)) {
    biomarkers_csv.cell(b.activation_ms).cell(b.rmp_mV).cell(b.apo_mV).cell(b.apd90_ms).cell(b.dvdt_max_mV_per_ms)
        .cell(b.apd50_ms);
  } else {  // empty where nothing was measured; "nan" stays a fired beat's unmeasured APD
    const std::string none;
    biomarkers_csv.cell(none).cell(format_number_or_empty(b.rmp_mV)).cell(none).cell(none).cell(none).cell(none);
  }
  biomarkers_csv.end_row();
  biomarkers_csv.flush();
}


// Split over ranks, every rank takes part (rank 0 gathers every cell's V)
// and rank 0 draws the snapshot as one process would.
void Simulation::Impl::snapshot_if_due(double t) {
  const SnapshotSpec& snap = scene.output.snapshots;
  if (!writes_folder || snap.every_ms <= 0) return;
  const double next = snap.from_ms + static_cast<double>(snapshots_taken) * snap.every_ms;
  if (t >= next - kTimeEpsilon_ms) {
    ++snapshots_taken;
    std::vector<double> every_cell;
    if (split.ranks) {
      if (mechanics) mechanics->solver().gather_on_rank0(false);  // (split: every body's place to rank 0)
      every_cell = voltage_of_every_cell();
      if (split.ranks->rank() != 0) return;
    }
    // Drawn on the writer's thread while the run goes on.
    // (The tissue itself is shared with the frame, not copied: the writer
    // finishes before the simulation, and so the tissue, goes.)
    const std::shared_ptr<const Tissue> built(std::shared_ptr<void>(), &tissue);
    const bool with_strain = strain_fields && (snap.vtk || snap.strain);
    auto frame = std::make_shared<SnapshotFrame>(
        take_snapshot(t, snap, built, mechanics_solver(), split.ranks ? every_cell : system.V_mV,
                      with_strain ? &strain_fields->now(mechanics->solver()) : nullptr));
    write_file([this, frame] { write_snapshot(out, scene.output.snapshots, scene.output.vtk_format, scene.name, *frame); });
  }
}

// A picture or snapshot file, on the writer's thread while the run goes
// on. When the cells' threads hold every core, one of them is lent to the
// writer until it is done (the cells step on one thread fewer meanwhile):
// the cells' threads wait for each other every step, so a writer sharing a
// core with one of them stalls both (in the Fig. 3 run on 2 cores its
// pictures cost about twice their own time that way).
void Simulation::Impl::write_file(std::function<void()> job) {
  writer.post(std::move(job));
  ThreadGovernor& governor = system.thread_governor();
  if (governor.lent() == 0 && governor.threads() > 1 && governor.threads() >= omp_get_num_procs())
    governor.lend(1);
}

// The core lent to the writer back to the cells once its pictures are done.
void Simulation::Impl::reclaim_writer_core() {
  ThreadGovernor& governor = system.thread_governor();
  if (governor.lent() > 0 && writer.idle()) governor.lend(0);
}

// The progress line (RunOptions::progress) and callback (on_progress), every
// output.progress_every_s of wall time.
void Simulation::Impl::report_progress(std::chrono::steady_clock::time_point now, double t_new) {
  if ((options.progress || options.on_progress) && scene.output.progress_every_s > 0 &&
      std::chrono::duration<double>(now - times.last_progress).count() >= scene.output.progress_every_s) {
    times.last_progress = now;
    if (options.on_progress) options.on_progress(t_new);
    if (!options.progress) return;
    const double elapsed = std::chrono::duration<double>(now - times.started).count();
    const double left = elapsed / t_new * (scene.duration_ms - t_new);
    std::fprintf(stderr, "\r  t = %.1f / %.1f ms   %.3g ms simulated per s   about %.0f s left   ",
                 t_new, scene.duration_ms, t_new / elapsed, left);
    std::fflush(stderr);
  }
}


// A failed run keeps what was written: the pictures already taken are
// finished (an error in them is logged; the run's own error stands).
void Simulation::Impl::finish_writing() {
  try {
    writer.finish();
  } catch (const std::exception& e) {
    warnings.push_back(std::string("picture not written: ") + e.what());
  }
}

// Clamped lookup tables, mechanics' report, and how the run ended.
void Simulation::Impl::log_run_end() {
  for (const auto& pop : system.populations)
    if (pop.table && pop.table->clamp_count() > 0)
      log->warn("lookup tables: {} model {}: V left the table [{:g}, {:g}] mV in {} cell evaluations "
                "(rates clamped to the table's ends)",
                cell_type_name(pop.type), pop.info().name, pop.table->v_min(), pop.table->v_max(),
                pop.table->clamp_count());
  if (mechanics) log->info("mechanics: {}", mechanics->report());
  if (const auto& governor = system.thread_governor(); governor.adapting())
    log->info("threads auto: the cell models' loop ran {} steps on {} threads and {} on one ({} switches)",
              governor.calls_on_more(), governor.max_threads(), governor.calls_on_one(), governor.switches());
  if (const auto report = integrator ? integrator->report() : integrator_report; !report.empty())
    log->info("integrator: {}", report);
  if (status == "failed") log->error("run failed: {}", error);
  else if (status == "interrupted")
    log->warn("run interrupted: {} of {} ms simulated in {:.3f} s wall, {} steps", t_reached_ms, scene.duration_ms,
              times.wall_s, steps);
  else log->info("run completed: {} ms simulated in {:.3f} s wall, {} steps", scene.duration_ms, times.wall_s, steps);
}

// report.html from the folder as written and the run's summary (a failed
// or interrupted run's too), then summary.json, once: with the report's own
// time as report_time_s, so its cost beside the run's wall time can be read
// off every run. A report that cannot be written is a warning: the run's
// results stand.
void Simulation::Impl::write_report_and_summary() {
  log->flush();  // the report shows run.log
  json s = summary();
  const auto start = Clock::now();
  try {
    write_run_report(out, s);
  } catch (const std::exception& e) {
    log->warn("report.html not written: {}", e.what());
  }
  const double report_s = seconds_since(start);
  log->info("report.html written in {:.3f} s ({:.2f} % of the run's wall time)", report_s,
            times.wall_s > 0 ? 100 * report_s / times.wall_s : 0.0);
  s["report_time_s"] = report_s;
  write_summary(out, s);
}

}  // namespace fibrodem
