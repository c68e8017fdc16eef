// output.reentry's sampling (docs/topics/arrhythmia.md): V of every cell
// (and with mechanics each cell's fibre stretch) at the sample times,
// gathered on rank 0 when split over ranks, kept on disk beside the
// checkpoints (run/frame_log.hpp) so that a resumed run measures the whole
// record, and measured at the run's end.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "run/checkpoint_dir.hpp"
#include "run/frame_log.hpp"
#include "run/reentry_maps.hpp"
#include "run/simulation_impl.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

namespace {
// The logs' names in the checkpoints' folder.
constexpr const char* kVoltageFramesLog = "reentry_V.frames";
constexpr const char* kStretchFramesLog = "reentry_stretch.frames";
}  // namespace

// output.reentry: V of every cell at from_ms + k every_ms, linear between
// the ends of the step that holds the sample time (exact on the steps of a
// fixed-step method when every_ms is a multiple of its dt).
void Simulation::Impl::start_reentry_sampling(double t) {
  if (!scene.output.reentry.on) return;
  reentry.frames = VoltageFrames(tissue.cell_count());
  system.gather_voltage();
  reentry.V_previous = system.V_mV;
  const bool holds_frames = !split.ranks || split.ranks->rank() == 0;
  if (holds_frames) reentry.frame_V.assign(tissue.cell_count(), 0.0);
  if (split.ranks) reentry.own_V.assign(split.share.owned.size(), 0.0);
  const auto& spec = scene.output.reentry;
  const long long last = static_cast<long long>(std::floor((scene.duration_ms - spec.from_ms) / spec.every_ms + 1e-9));
  const auto samples_from = [last](long long k) { return static_cast<std::size_t>(std::max(0LL, last - k + 1)); };
  ReentryResume& resumed = reentry.resumed;
  if (resumed.next_sample < 0 && checkpoints.resume_point)
    log->warn("resume: the checkpoint holds no count of re-entry frames (an earlier build of fibrodem's): "
              "re-entry is measured from t = {:g} ms", t);
  bool read_back = !(resumed.next_sample >= 0 && holds_frames) || read_back_frames(samples_from(resumed.next_sample));
  // Split over ranks, rank 0 reads the frames back and every rank follows
  // its outcome: the ranks take the same samples (each a collective gather).
  if (split.reductions && checkpoints.resume_point) read_back = split.reductions->largest(read_back ? 0 : 1) == 0;
  if (!read_back) resumed = {};
  // The first sample at or after t, unless the checkpoint's frames hold the samples before it.
  reentry.next_sample = resumed.next_sample >= 0 ? resumed.next_sample
                        : t <= spec.from_ms      ? 0
                                                 : static_cast<long long>(std::ceil((t - spec.from_ms) / spec.every_ms - 1e-9));
  // Every frame's room at once (CellFrames::reserve_more): the samples
  // from next_sample to the last at or before the run's end.
  const std::size_t to_come = samples_from(reentry.next_sample);
  if (holds_frames) reentry.frames.reserve_more(to_come);
  if (strain_fields) strain_fields->reserve_samples(to_come);
  if (holds_frames && checkpoints.every_ms > 0) keep_frames_on_disk();
  if (resumed.next_sample < 0 &&
      std::abs(t - (spec.from_ms + static_cast<double>(reentry.next_sample) * spec.every_ms)) < kTimeEpsilon_ms) {
    if (split.ranks) add_reentry_frame_over_ranks(t, nullptr);
    else reentry.frames.add(t, system.V_mV);
    if (strain_fields) strain_fields->sample_now(t, mechanics->solver());
    ++reentry.next_sample;
  }
}

// A resumed run: the frames its checkpoint counts, read back from the logs
// beside it (run/frame_log.hpp), with room for the `to_come` samples. False,
// with a warning, if a log cannot give them: re-entry is then measured from
// the resume, as without logs.
bool Simulation::Impl::read_back_frames(std::size_t to_come) {
  const ReentryResume& resumed = reentry.resumed;
  const fs::path from = checkpoints.resume_point->file.parent_path();
  try {
    VoltageFrames V(tissue.cell_count());
    V.reserve_more(resumed.frames + to_come);
    read_frame_log(from / kVoltageFramesLog, resumed.frames, V);
    if (strain_fields) strain_fields->read_back(from / kStretchFramesLog, resumed.stretch_frames, to_come);
    reentry.frames = std::move(V);
    return true;
  } catch (const CheckpointError& e) {
    log->warn("resume: {}; re-entry is measured from t = {:g} ms", e.what(), start_ms);
    return false;
  }
}

// With checkpoints, the frames go to disk at each (checkpoint_fields), so
// that a resumed run measures from from_ms. A run resumed in its own
// folder continues its logs after the checkpoint's frames; elsewhere they
// start afresh and the first checkpoint writes every frame held.
void Simulation::Impl::keep_frames_on_disk() {
  const fs::path here = checkpoint_path(run_folder, 0).parent_path();
  fs::create_directories(here);
  reentry.V_log.emplace(here / kVoltageFramesLog);
  if (strain_fields) reentry.stretch_log.emplace(here / kStretchFramesLog);
  const ReentryResume& resumed = reentry.resumed;
  std::error_code ec;
  if (resumed.next_sample < 0 || !fs::equivalent(here, checkpoints.resume_point->file.parent_path(), ec)) return;
  reentry.V_log->continue_after(resumed.frames, tissue.cell_count());
  if (strain_fields) reentry.stretch_log->continue_after(resumed.stretch_frames, tissue.cell_count());
}

// A checkpoint's share of the re-entry sampling: the next sample's index
// (every rank), and on the rank holding the frames every frame so far
// written to the logs and their counts.
void Simulation::Impl::save_reentry(CheckpointFields& f) {
  if (!scene.output.reentry.on) return;
  f.put_integer("reentry.next_sample", reentry.next_sample);
  if (reentry.V_log) {
    reentry.V_log->append_new(reentry.frames);
    f.put_integer("reentry.frames", static_cast<long long>(reentry.V_log->written()));
  }
  if (reentry.stretch_log) {
    reentry.stretch_log->append_new(strain_fields->stretch_frames());
    f.put_integer("reentry.stretch_frames", static_cast<long long>(reentry.stretch_log->written()));
  }
}

void Simulation::Impl::restore_reentry(const CheckpointFields& f) {
  reentry.resumed = {};
  if (!scene.output.reentry.on || !f.has("reentry.next_sample")) return;
  reentry.resumed.next_sample = f.integer("reentry.next_sample");
  if (f.has("reentry.frames")) reentry.resumed.frames = static_cast<std::size_t>(f.integer("reentry.frames"));
  if (f.has("reentry.stretch_frames"))
    reentry.resumed.stretch_frames = static_cast<std::size_t>(f.integer("reentry.stretch_frames"));
}

void Simulation::Impl::sample_reentry_if_due(double t_old, double t_new) {
  if (!scene.output.reentry.on) return;
  const auto& spec = scene.output.reentry;
  for (;;) {
    const double next = spec.from_ms + static_cast<double>(reentry.next_sample) * spec.every_ms;
    if (next > t_new + kTimeEpsilon_ms) break;
    ++reentry.next_sample;
    if (next < t_old - kTimeEpsilon_ms) continue;  // before a resumed run's start
    const double w = t_new > t_old ? std::clamp((next - t_old) / (t_new - t_old), 0.0, 1.0) : 1.0;
    if (strain_fields) strain_fields->due(next, w, mechanics->solver());  // (the DEM is still at t_old)
    if (split.ranks) {
      add_reentry_frame_over_ranks(next, &w);
      continue;
    }
    std::vector<double>& V = reentry.frame_V;
    for (std::size_t c = 0; c < V.size(); ++c) V[c] = reentry.V_previous[c] + w * (system.V_mV[c] - reentry.V_previous[c]);
    reentry.frames.add(next, V);
  }
  reentry.V_previous = system.V_mV;
}

// Split over ranks, each rank's cells' V at a sample (interpolated with
// weight *w, or V at the step's end without one), gathered on rank 0 into
// the frame one process would add (the same arithmetic on the same values:
// the same bits). Every rank steps to the same times (a fixed step, or the
// adaptive step control's agreed steps and stops), so every rank comes here
// for the same samples, in the same order: the gather is collective.
void Simulation::Impl::add_reentry_frame_over_ranks(double t, const double* w) {
  // (The own cells are the first of the held ones.)
  const double* V = system.V_mV.data();
  const double* V_before = reentry.V_previous.data();
  for (std::size_t c = 0; c < reentry.own_V.size(); ++c)
    reentry.own_V[c] = w ? V_before[c] + *w * (V[c] - V_before[c]) : V[c];
  gather_by_cell(*split.ranks, split.layout, reentry.own_V.data(), reentry.gathered_V, reentry.frame_V);
  if (split.ranks->rank() == 0) reentry.frames.add(t, reentry.frame_V);
}

// summary.json's "reentry", phase_singularities.csv and the re-entry maps,
// from the samples (split over ranks: on rank 0, which holds them and every
// beat).
void Simulation::Impl::measure_reentry() {
  if (!scene.output.reentry.on) return;
  if (split.ranks && split.ranks->rank() != 0) return;
  const auto& spec = scene.output.reentry;
  const ReentrySettings settings{.every_ms = spec.every_ms, .from_ms = spec.from_ms, .tau_ms = spec.tau_ms,
                                 .V_star_mV = spec.V_star_mV, .link_mm = spec.link_mm, .f_min_hz = spec.f_min_hz,
                                 .f_max_hz = spec.f_max_hz, .clinical_f_min_hz = spec.clinical_f_min_hz,
                                 .clinical_f_max_hz = spec.clinical_f_max_hz,
                                 .ps_density_bin_mm = spec.ps_density_bin_mm};
  ReentryMaps maps;
  const StretchFrames* stretch = strain_fields ? &strain_fields->stretch_frames() : nullptr;
  reentry.measured = analyse_reentry(tissue, reentry.frames, settings, system.stimulus.onsets(t_reached_ms), beats,
                                     out, &maps, stretch);
  if (out.empty()) return;
  // The tip paths over the fibre stretch (with mechanics) or V at the last sample.
  MapField last;
  if (stretch && stretch->count() > 0) {
    const float* lambda = stretch->frame(stretch->count() - 1);
    last = {std::vector<double>(lambda, lambda + stretch->cells), "fibre stretch",
            fmt::format("fibre stretch at t = {:g} ms", stretch->t_ms.back())};
  } else if (reentry.frames.count() > 0) {
    const float* V = reentry.frames.frame(reentry.frames.count() - 1);
    last = {std::vector<double>(V, V + reentry.frames.cells), "V (mV)",
            fmt::format("V at t = {:g} ms", reentry.frames.t_ms.back())};
  }
  reentry.measured["beat_maps_drawn"] =
      write_reentry_maps(out, scene.name, tissue, maps, scene.output.vtk_format, last);
}

}  // namespace fibrodem
