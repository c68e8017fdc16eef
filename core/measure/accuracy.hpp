// Accuracy of a run against a reference run of the same scene
// (docs/topics/numerics.md#what-accuracy-costs; docs/reference/references.md#measurement-conventions,
// docs/reference/references.md#integrator-cost): the error in the
// membrane potential traces, in APD90, in activation time and in conduction
// velocity. Pure functions of recorded results, so that they can be checked on
// synthetic runs; `record_of` takes what they need from a finished Simulation.
//
//   V error          over every traced V column present in both runs and the
//                    sample times common to both (matched to 1e-6 ms): RMS and
//                    max of |V - V_ref| [mV]
//   APD90 error      max over (cell, beat) of |APD90 - APD90_ref| [ms]
//   activation error max over (cell, beat) of |t_act - t_act_ref| [ms]
//   CV error         |CV - CV_ref| [cm/s] and |CV - CV_ref| / |CV_ref|
// A beat of the reference that the candidate lacks, or whose APD90 is finite in
// one run and not in the other (the action potential did not repolarise, or
// arose where it should not), is a mismatch: the error is +inf and counted.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "measure/run_record.hpp"

namespace fibrodem {

struct AccuracyErrors {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double v_rms_mV = nan, v_max_mV = nan;
  long long v_samples = 0;  // values compared (columns x common times)
  double apd90_max_ms = nan;
  double activation_max_ms = nan;
  int beats_compared = 0;  // (cell, beat) pairs of the reference
  int beats_mismatched = 0;
  double cv_abs_cm_per_s = nan, cv_rel = nan;
};

// `variable`: the traced variable compared (columns named variable_CELL).
AccuracyErrors compare_runs(const RunRecord& reference, const RunRecord& candidate,
                            const std::string& variable = "V");

// One run of an accuracy ladder: a method at a step (dt [ms]) or tolerance (rtol).
struct LadderRun {
  std::string method;        // euler | rush_larsen | rush_larsen2 | cvode | adaptive | auto
  double setting = 0;        // dt_ms; rtol for cvode; rtol = atol for adaptive; accuracy_ms for auto
  std::string chosen;        // auto: what it chose
  bool completed = false;
  std::string error;         // why it failed
  double wall_s = 0;         // run only (setup excluded); min over repeats
  long long steps = 0;       // integrator steps (CVODE: its internal steps)
  long long cells = 0;
  long long cell_steps() const { return steps * cells; }
  AccuracyErrors errors;
};

// The completed run of least wall time whose metric is <= threshold and stays
// so for every finer run of its method (smaller dt or rtol; all of them must
// have completed; finer: a smaller setting, whatever the method), so that a lucky cancellation of errors at one step does not
// count. NaN metrics never qualify; `method` non-empty restricts to that method.
std::optional<std::size_t> cheapest_meeting(const std::vector<LadderRun>& runs,
                                            const std::function<double(const AccuracyErrors&)>& metric,
                                            double threshold, const std::string& method = "");

}  // namespace fibrodem
