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
#include "run/checkpoint_recut.hpp"
#include "run/run_summary.hpp"
#include "run/simulation_impl.hpp"
#include "tissue/cell_partition.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

namespace {

std::string over_ranks_text(long long ranks) {
  return ranks == 1 ? std::string("in one process") : "split over " + std::to_string(ranks) + " MPI ranks";
}

// The beats in a part of the cells `pick` picks, added to `beats`.
void take_beats(const CheckpointFields& part, const CellPick& pick, std::vector<BeatBiomarkers>& beats) {
  const std::string raw = part.text("run.beats");
  for (std::size_t at = 0; at + sizeof(BeatBiomarkers) <= raw.size(); at += sizeof(BeatBiomarkers)) {
    int cell = -1;
    std::memcpy(&cell, raw.data() + at + offsetof(BeatBiomarkers, cell), sizeof cell);
    if (!pick.picks(cell)) continue;
    beats.emplace_back();
    std::memcpy(static_cast<void*>(&beats.back()), raw.data() + at, sizeof(BeatBiomarkers));
  }
}

}  // namespace

// output.checkpoint: a fixed-step method's checkpoints fall on its steps
// (and on its coupling steps), so that a resumed run takes the same steps.
void Simulation::Impl::plan_checkpoints() {
  checkpoints.every_ms = scene.output.checkpoint.every_ms;
  if (checkpoints.every_ms <= 0) return;
  if (!writes_folder) {  // (every rank of a split run knows rank 0's folder)
    checkpoints.every_ms = 0;
    return;
  }
  if (scene.solver.fixed_step()) {
    const double quantum = scene.solver.dt_ms * std::max(1, system.coupling_every);
    checkpoints.every_ms = std::max(1.0, std::round(checkpoints.every_ms / quantum)) * quantum;
  }
  plan.notes.push_back(fmt::format("checkpoints every {:g} ms, the newest {} kept, in {}", checkpoints.every_ms,
                                   scene.output.checkpoint.keep,
                                   (run_folder / "checkpoints").string()));
  if (const char* kill = std::getenv("FIBRODEM_TEST_KILL")) {
    long long n = 0;
    if (std::sscanf(kill, "step:%lld", &n) == 1) checkpoints.kill_at_step = n;
    else if (std::sscanf(kill, "checkpoint:%lld", &n) == 1) checkpoints.kill_in_checkpoint = n;
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
  save_reentry(f);
  return f;
}

// Every output up to t on disk first (pictures included), then the state.
// Split over ranks, each rank's own cells, trackers, traces and beats:
// rank r > 0 writes them to its part (rank_checkpoint_path), rank 0 to the
// checkpoint itself, last, with the rank count.
void Simulation::Impl::write_checkpoint(double t) {
  ScopeTimer timer(times.output_s);
  writer.finish();
  const fs::path file = checkpoint_path(run_folder, t);
  fs::create_directories(file.parent_path());
  ++checkpoints.written;
  const bool kill = checkpoints.written == checkpoints.kill_in_checkpoint;
  CheckpointFields fields = checkpoint_fields(t);
  if (split.ranks) {
    fields.put_integer("run.mpi_ranks", split.ranks->size());
    fields.put_integer("run.mpi_rank", split.ranks->rank());
    write_rank_checkpoint(file, fields, kill);
    if (split.ranks->rank() != 0) return;
  }
  write_checkpoint_file(file, fields, [kill] {
    if (kill) std::raise(SIGKILL);
  });
  prune_checkpoints(out, scene.output.checkpoint.keep);
  checkpoints.last = {{"file", fs::relative(file, out).string()}, {"time_ms", t}};
  log->info("checkpoint at t = {:g} ms: {}", t, file.string());
  write_summary(out, summary());
}

// Rank r > 0 writes its part; every rank then waits for every part (rank 0
// gathers a word from each once written), so that the checkpoint rank 0
// writes after exists only with every part whole beside it.
void Simulation::Impl::write_rank_checkpoint(const fs::path& file, const CheckpointFields& mine, bool kill) {
  const int rank = split.ranks->rank();
  if (rank != 0) {
    write_checkpoint_file(rank_checkpoint_path(file, rank), mine, [kill] {
      if (kill) std::raise(SIGKILL);
    });
  }
  split.ranks->gather({static_cast<double>(rank)});
}

// Split over another number of ranks than the checkpoint's (one process
// counting as one), every rank reads the parts that hold its cells one at
// a time and takes its own cells' fields out of each
// (run/checkpoint_recut.hpp); over the same number, each rank reads its own
// part.
//
// The checkpoint's fields are taken out of the one found (nothing reads
// them after this), so the run does not hold them while it goes on; cut
// again, its fields are copied once, for this rank's cells.
void Simulation::Impl::resume() {
  FoundCheckpoint& found = *checkpoints.resume_point;
  const long long written = ranks_of_checkpoint(found.fields), here = split.ranks ? split.ranks->size() : 1;
  try {
    CheckpointFields checkpoint = std::move(found.fields);
    if (written != here) {
      restore(recut_checkpoint(found.file, checkpoint));
    } else if (split.ranks && split.ranks->rank() != 0) {
      restore(read_checkpoint_part(found.file, checkpoint, split.ranks->rank()));
    } else {
      restore(checkpoint);
    }
    // The DEM split over ranks: every rank takes the whole tissue's from the
    // checkpoint itself (rank 0's, written as one process writes it).
    if (mechanics && mechanics->split()) mechanics->restore(checkpoint, start_ms);
  } catch (const CheckpointError& e) {
    throw CheckpointError("checkpoint " + found.file.string() + " does not fit this run: " + e.what());
  }
  for (const auto& skipped : found.skipped) log->warn("resume: passed over {}", skipped);
  checkpoints.resumed_from = {{"file", fs::relative(found.file, run_folder).string()}, {"time_ms", start_ms}};
  if (written != here)
    log->info("resumed from checkpoint {} at t = {:g} ms (written {}; its parts cut again for this run, {})", found.file.string(), start_ms,
              over_ranks_text(written), over_ranks_text(here));
  else
    log->info("resumed from checkpoint {} at t = {:g} ms", found.file.string(), start_ms);
}

// What this rank would have written at the checkpoint's time had the run
// been split as it is now, from the parts of the checkpoint `file` (rank
// 0's: `checkpoint`) taken one at a time: its populations' and its
// biomarker tracker's cells cell by cell, every part's trace columns (each
// rank reads its own), the beats of its cells in one process's order (by
// beat, then cell); the rest (time, steps, rank 0's outputs and mechanics)
// as the checkpoint has it.
CheckpointFields Simulation::Impl::recut_checkpoint(const fs::path& file, const CheckpointFields& checkpoint) const {
  CellStatesRecut cell_states(system, checkpoint, false);
  std::vector<int> own;  // the tracker's cells: this rank's, in increasing tissue order
  own.reserve(system.numbering.own());
  for (std::size_t c = 0; c < system.numbering.own(); ++c) own.push_back(system.numbering.tissue_cell(c));
  CellPick tracker_cells(own, tissue.cell_count());
  std::vector<std::string> tracker_rows;
  for (const auto& name : BiomarkerTracker::per_cell_number_fields())
    if (checkpoint.has(name)) tracker_rows.push_back(name);
  std::vector<BeatBiomarkers> own_beats;
  CheckpointFields f;
  const int read = take_checkpoint_parts(
      file, checkpoint, checkpoint_parts_of_own_cells(checkpoint),
      [&] { return cell_states.complete() && tracker_cells.complete(); },
      [&](const CheckpointFields& part, int r) {
        cell_states.take(part, r);
        tracker_cells.take(part, r, own_cells_of_part(part), tracker_rows, {BiomarkerTracker::kPerCellBytesField});
        take_beats(part, tracker_cells, own_beats);
        for (const auto& name : part.names_starting("traces.column.")) f.copy_from(part, name);
      });
  log->info("resume: {} of the checkpoint's {} parts read for this rank's cells", read,
            ranks_of_checkpoint(checkpoint));
  cell_states.put_into(f);
  tracker_cells.put_into(f);
  std::stable_sort(own_beats.begin(), own_beats.end(), in_beat_order);
  f.put_bytes("run.beats", own_beats.data(), own_beats.size() * sizeof(BeatBiomarkers));
  // The rest as the checkpoint has it (not a copy of the whole and then
  // these over it: every cell's fields twice more in memory).
  for (const auto& name : checkpoint.names_starting(""))
    if (!f.has(name)) f.copy_from(checkpoint, name);
  return f;
}

// The parts of a checkpoint (rank 0's fields) that hold this rank's cells,
// if the run that wrote it over N ranks was split as this tissue's
// partition over N cuts it, as it was unless the two runs' partitions
// differ (take_checkpoint_parts then reads the others too): every part in
// one process.
std::vector<int> Simulation::Impl::checkpoint_parts_of_own_cells(const CheckpointFields& checkpoint) const {
  const long long written = ranks_of_checkpoint(checkpoint);
  std::vector<char> holds(static_cast<std::size_t>(written), split.ranks ? 0 : 1);
  if (split.ranks && written > 1) {
    // (A rank holding part of the graph cuts with the whole graph's pitch.)
    const auto part_then = part_of_cells(tissue, static_cast<int>(written), scene.solver.partition,
                                         split.cut ? &split.cut->pitch : nullptr);
    for (std::size_t c = 0; c < system.numbering.own(); ++c)
      holds[static_cast<std::size_t>(part_then(system.numbering.tissue_cell(c)))] = 1;
  }
  std::vector<int> parts;
  for (std::size_t r = 0; r < holds.size(); ++r)
    if (holds[r]) parts.push_back(static_cast<int>(r));
  return parts;
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
  restore_reentry(f);
  // Split over ranks, traces.csv and biomarkers.csv are written whole at the
  // end (from the samples and beats held); in one process they are written
  // as the run goes, so a split run's checkpoint resumed in one process
  // writes what it holds first.
  const bool written_split = ranks_of_checkpoint(f) > 1;
  const bool streams = !out.empty() && !split.ranks;
  traces.load(f, streams && !written_split ? out / "traces.csv" : fs::path());
  if (streams && written_split) traces.write_csv(out / "traces.csv");
  if (streams && !written_split) {
    biomarkers_csv = CsvWriter::resume(out / "biomarkers.csv", static_cast<std::uintmax_t>(f.integer("run.biomarkers_csv_bytes")));
  } else if (!out.empty()) {
    open_biomarkers_csv();
    if (streams)
      for (const auto& b : beats) write_biomarker_row(b);
  }
  if (mechanics && !mechanics->split()) mechanics->restore(f, start_ms);  // (split: resume())
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
    // (A rank holding part of the cells is given its own cells' beats alone.)
    if (cell < 0 || static_cast<std::size_t>(cell) >= tissue.cell_count() ||
        (tissue.cells_partial() && !system.numbering.owns(cell)) ||
        type != static_cast<std::underlying_type_t<CellType>>(tissue.type_of(cell)))
      throw CheckpointError("its biomarkers name a cell this tissue does not have");
    std::memcpy(static_cast<void*>(&beats[i]), beat, sizeof(BeatBiomarkers));
  }
}

}  // namespace fibrodem
