// An accuracy ladder: what accuracy costs in time for one scene
// (docs/reference/references.md#integrator-cost: Cooper, Spiteri & Mirams 2015
// rank integrators by the largest step within an error).
//
// The scene is run with each integrator over a ladder of settings: fixed-step
// methods (euler, rush_larsen, rush_larsen2) over steps dt, CVODE over
// relative tolerances (atol = ratio x rtol), adaptive over tolerances (rtol =
// atol = tol), auto over the APD90 accuracy asked (solver.accuracy). Each run
// is measured against a reference: CVODE at a relative tolerance two orders
// of magnitude tighter than the tightest on the ladder (measure/accuracy.hpp
// says how: V RMS and max over the traced cells and common sample times,
// APD90 and activation time max over cells and beats, CV absolute and
// relative). CVODE at 10x the reference's rtol, measured the same way, shows
// how far the reference itself is resolved. Both evaluate the exact model
// (solver.lookup_tables removed), so ladder runs with lookup tables are
// measured against the table-free solution.
//
// Runs are single-threaded, trace V alone and write nothing; the wall time is
// that of Simulation::run (setup excluded), the least of `repeat` runs. A run
// that fails (blow-up) is kept as failed, with its error.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "measure/accuracy.hpp"
#include "run/run_record.hpp"
#include "scene/scene.hpp"

namespace fibrodem {

// What to run. Its errors name the options of `fibrodem bench accuracy`
// (--methods, --dt, ...) that set each field.
struct AccuracyLadderSpec {
  json manifest;                     // the scene (overrides applied)
  std::vector<std::string> methods;  // empty: all (euler, rush_larsen, rush_larsen2, cvode, adaptive, auto)
  std::vector<double> dt_ms;         // fixed-step ladder; empty: the default
  std::vector<double> rtol;          // CVODE ladder; empty: the default
  std::vector<double> tol;           // adaptive ladder (rtol = atol); empty: the default
  std::vector<double> accuracy_ms;   // auto ladder (solver.accuracy); empty: the default
  double atol_ratio = 1e-2;          // CVODE atol = ratio x rtol
  double reference_rtol = 0;         // 0: the tightest rtol / 100
  double every_ms = 0;               // V sample interval; 0: the manifest's output.traces.every_ms
  int repeat = 1;                    // runs per rung; the wall time is the least
};

// One run of the scene, as the ladder keeps it.
struct LadderOutcome {
  bool completed = false;
  std::string error;
  double wall_s = 0;
  long long steps = 0, cells = 0;
  std::string chosen;  // auto: the method it chose, with its settings
  RunRecord record;
};

// A ladder set up (plan_accuracy_ladder) and then run (run_accuracy_ladder).
struct AccuracyLadder {
  json base;  // the manifest every run starts from: V traced alone, no output folder
  std::vector<std::string> methods;
  std::vector<double> dt_ms, rtol, tol, accuracy_ms;  // the ladders, defaults filled in
  double atol_ratio = 1e-2;
  double reference_rtol = 0, reference_atol = 0;
  int repeat = 1;
  Scene scene;  // the reference's (name, duration, traces)

  LadderOutcome reference, check;  // check: CVODE at 10 x the reference's rtol
  AccuracyErrors check_errors;     // the check against the reference
  std::vector<LadderRun> runs;     // the rungs, method by method
  bool has_cv() const { return reference.record.cv_cm_per_s.has_value(); }
};

// The ladder's set-up: defaults filled in and the settings checked before
// anything runs; throws ManifestError naming the option (or the manifest's
// JSON path) at fault.
AccuracyLadder plan_accuracy_ladder(const AccuracyLadderSpec& spec);

// Runs the reference, its check, then every rung; `progress` gets a line per
// run (without its newline). Throws std::runtime_error if the reference fails.
void run_accuracy_ladder(AccuracyLadder& ladder, const std::function<void(const std::string&)>& progress);

// A number in the ladder's tables and messages: blank for NaN, "inf" for infinity.
std::string accuracy_number(double v, const char* spec = "{:.3g}");

// "dt 0.01 ms", "rtol 1e-05", "tol 0.01", "accuracy 1 ms (cvode rtol 1e-05)".
std::string ladder_setting_text(const LadderRun& run);

}  // namespace fibrodem
