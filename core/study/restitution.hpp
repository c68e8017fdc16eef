// S1-S2 action-potential restitution (docs/topics/arrhythmia.md#restitution): the
// manifest's stimulus[1] (S2) is moved to each coupling interval after the
// last onset of stimulus[0] (S1), one run per interval by a sweep's point
// runner (study/sweep_point.hpp); each run's biomarkers.csv gives, per
// measured myocyte, the APD90 of the last S1 beat and the APD90 and APD50 of
// the S2 beat. The curve is APD against the diastolic interval DI = coupling
// interval - APD90 of the last S1 beat (the convention of the clinical
// S1-S2 protocol), measured per cell as the S2 activation minus the end of
// its last S1 action potential (activation + APD90), so that in tissue each
// cell's own interval counts. The effective refractory period (ERP) is the
// longest coupling interval whose S2 is not captured, refined by bisection
// against the shortest captured one above it.
//
// A cell's S2 beat is captured when its APD90 was measured and its
// amplitude (APO - RMP) is at least half that of its last S1 beat (a
// stimulus in the refractory period only depolarises the cell passively); a
// run is captured when at least `capture_fraction` of the measured cells are.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "study/sweep_point.hpp"

namespace fibrodem {

struct RestitutionPoint {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double interval_ms = 0;
  bool captured = false;
  std::size_t cells_measured = 0, cells_captured = 0;
  // Medians over the captured cells (NaN if none).
  double s1_apd90_ms = kNone, s2_apd90_ms = kNone, s2_apd50_ms = kNone, di_ms = kNone;
  bool refinement = false;  // run by the ERP bisection, not the scan
  std::string run;          // its folder, relative to the study's
  std::string error;        // why it failed
  bool reused = false;
};

struct RestitutionOptions {
  std::filesystem::path out;  // the study's folder (required)
  PointRunner runner;
  unsigned jobs = 0;                 // runs at once; 0: one per core
  std::vector<double> intervals_ms;  // empty: default_restitution_intervals
  std::vector<int> cells;            // measured cells; empty: every myocyte
  double capture_fraction = 0.5;
  double erp_resolution_ms = 1;      // bisection of the ERP; 0: none
  bool overwrite = false, report = false;
  std::function<void(const RestitutionPoint&)> on_run_done;  // one call at a time
};

struct RestitutionResult {
  std::vector<RestitutionPoint> points;  // by interval, decreasing
  // The ERP: the longest non-captured interval, within erp_resolution_ms of
  // a captured one above it; nullopt if every interval (or none) was
  // captured.
  std::optional<double> erp_ms;
};

// The S1 period down to 100 ms: 1000, 800, 600, 500, 400, 350, 300, then by
// 25 ms to 200 and by 10 ms to 100, the first value the S1 period if it is
// not on the list (intervals above it are dropped).
std::vector<double> default_restitution_intervals(const json& manifest);

// Where the runs go without --out: out/restitution_<the manifest's name>.
std::filesystem::path default_restitution_dir(const json& manifest);

// One run's point from its biomarkers.csv: S1's last beat and S2's beat
// numbers as biomarkers.csv counts beats. Where S2 came before the last S1
// beat repolarised (its APD90 unmeasured), the S1 beat before it stands in
// for its APD90, RMP and APO (the train's steady state).
RestitutionPoint restitution_point(const CsvTable& biomarkers, std::size_t s1_beat, std::size_t s2_beat,
                                   const std::vector<int>& cells, double capture_fraction);

// Runs the protocol into options.out: runs/ci_<ms>ms/, restitution.csv,
// restitution.json and restitution.png (APD90 and APD50 against DI).
RestitutionResult run_restitution(json manifest, RestitutionOptions options);

}  // namespace fibrodem
