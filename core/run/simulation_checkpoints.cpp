// Checkpoints (output.checkpoint): where they fall, what they hold (the cells,
// trackers, traces, outputs' lengths and the mechanics), and a run taken
// back to one (fibrodem resume; Simulation::resume_from).
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <type_traits>

#include "run/cell_state_checkpoint.hpp"
#include "run/run_summary.hpp"
#include "run/simulation_impl.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

// output.checkpoint: a fixed-step method's checkpoints fall on its steps
// (and on its coupling steps), so that a resumed run takes the same steps.
void Simulation::Impl::plan_checkpoints() {
  checkpoint_every_ms = scene.output.checkpoint.every_ms;
  if (checkpoint_every_ms <= 0) return;
  if (scene.output.dir.empty()) {
    checkpoint_every_ms = 0;
    return;
  }
  if (scene.solver.fixed_step()) {
    const double quantum = scene.solver.dt_ms * std::max(1, system.coupling_every);
    checkpoint_every_ms = std::max(1.0, std::round(checkpoint_every_ms / quantum)) * quantum;
  }
  plan.notes.push_back(fmt::format("checkpoints every {:g} ms, the newest {} kept, in {}", checkpoint_every_ms,
                                   scene.output.checkpoint.keep,
                                   (fs::path(scene.output.dir) / "checkpoints").string()));
  if (const char* kill = std::getenv("FIBRODEM_TEST_KILL")) {
    long long n = 0;
    if (std::sscanf(kill, "step:%lld", &n) == 1) kill_at_step = n;
    else if (std::sscanf(kill, "checkpoint:%lld", &n) == 1) kill_in_checkpoint = n;
  }
}

// Everything the run holds at t (the end of a step, between integrator
// segments), for a checkpoint.
CheckpointFields Simulation::Impl::checkpoint_fields(double t) {
  CheckpointFields f;
  f.put("run.time_ms", t);
  f.put_text("run.scene", scene.manifest.dump(-1, ' ', false, json::error_handler_t::replace));
  f.put_integer("run.steps", steps);
  f.put_integer("run.snapshots_taken", snapshots_taken);
  static_assert(std::is_trivially_copyable_v<BeatBiomarkers>);
  f.put_integer("run.beat_bytes", static_cast<long long>(sizeof(BeatBiomarkers)));
  f.put_bytes("run.beats", beats.data(), beats.size() * sizeof(BeatBiomarkers));
  if (biomarkers_csv.is_open()) f.put_integer("run.biomarkers_csv_bytes", static_cast<long long>(biomarkers_csv.bytes_written()));
  save_cell_states(system, f);
  tracker->save(f);
  traces.save(f);
  if (mechanics) mechanics->save(f);
  return f;
}

// Every output up to t on disk first (pictures included), then the state.
void Simulation::Impl::write_checkpoint(double t) {
  ScopeTimer timer(output_seconds);
  writer.finish();
  const fs::path file = checkpoint_path(out, t);
  fs::create_directories(file.parent_path());
  ++checkpoints_written;
  const bool kill = checkpoints_written == kill_in_checkpoint;
  write_checkpoint_file(file, checkpoint_fields(t), [kill] {
    if (kill) std::raise(SIGKILL);
  });
  prune_checkpoints(out, scene.output.checkpoint.keep);
  last_checkpoint = {{"file", fs::relative(file, out).string()}, {"time_ms", t}};
  log->info("checkpoint at t = {:g} ms: {}", t, file.string());
  write_summary(out, summary());
}

void Simulation::Impl::resume() {
  try {
    restore(resume_point->fields);
  } catch (const CheckpointError& e) {
    throw CheckpointError("checkpoint " + resume_point->file.string() + " does not fit this run: " + e.what());
  }
  for (const auto& skipped : resume_point->skipped) log->warn("resume: passed over {}", skipped);
  resumed_from = {{"file", fs::relative(resume_point->file, out).string()}, {"time_ms", start_ms}};
  log->info("resumed from checkpoint {} at t = {:g} ms", resume_point->file.string(), start_ms);
}

// The run as a checkpoint left it (the scene must be the one it was written for).
void Simulation::Impl::restore(const CheckpointFields& f) {
  if (f.text("run.scene") != scene.manifest.dump(-1, ' ', false, json::error_handler_t::replace))
    throw CheckpointError("it was written for another scene (its manifest differs from summary.json's)");
  start_ms = t_reached_ms = f.number("run.time_ms");
  if (!(start_ms >= 0 && start_ms <= scene.duration_ms))
    throw CheckpointError(fmt::format("its time, {} ms, is outside this scene's [0, {}] ms", start_ms,
                                      scene.duration_ms));
  steps = f.integer("run.steps");
  snapshots_taken = f.integer("run.snapshots_taken");
  if (f.integer("run.beat_bytes") != static_cast<long long>(sizeof(BeatBiomarkers)))
    throw CheckpointError("its biomarkers were written by another build of fibrodem");
  restore_beats(f);
  load_cell_states(system, f, true);
  tracker->load(f);
  traces.load(f, out.empty() ? fs::path() : out / "traces.csv");
  if (!out.empty())
    biomarkers_csv = CsvWriter::resume(out / "biomarkers.csv", static_cast<std::uintmax_t>(f.integer("run.biomarkers_csv_bytes")));
  if (mechanics) mechanics->restore(f, start_ms);
}

// The beats measured so far, each checked (a cell of the tissue, its type)
// before it is taken: a byte of a type must not become an invalid enum.
void Simulation::Impl::restore_beats(const CheckpointFields& f) {
  const std::string raw = f.text("run.beats");
  if (raw.size() % sizeof(BeatBiomarkers) != 0) throw CheckpointError("its biomarkers are cut short");
  beats.resize(raw.size() / sizeof(BeatBiomarkers));
  for (std::size_t i = 0; i < beats.size(); ++i) {
    const char* beat = raw.data() + i * sizeof(BeatBiomarkers);
    int cell = 0;
    std::underlying_type_t<CellType> type{};
    std::memcpy(&cell, beat + offsetof(BeatBiomarkers, cell), sizeof cell);
    std::memcpy(&type, beat + offsetof(BeatBiomarkers, type), sizeof type);
    if (cell < 0 || static_cast<std::size_t>(cell) >= tissue.cell_count() ||
        type != static_cast<std::underlying_type_t<CellType>>(tissue.type[static_cast<std::size_t>(cell)]))
      throw CheckpointError("its biomarkers name a cell this tissue does not have");
    std::memcpy(static_cast<void*>(&beats[i]), beat, sizeof(BeatBiomarkers));
  }
}

}  // namespace fibrodem
