// Action-potential biomarkers per cell and beat, measured on the fly at every
// integrator step (docs/reference/references.md#measurement-conventions; seed paper section 3):
//   activation time  time of max dV/dt in the beat
//   RMP              V just before the beat's stimulus onset, or (with
//                    use_pre_upstroke_rmp) the mean V over a window before the
//                    cell's own activation (measure/pre_upstroke_window.hpp);
//                    the APD levels use the onset V either way
//   APO              peak potential (signed: a fibroblast's may be negative)
//   APD_X            activation to the last downward crossing of
//                    V_peak - X/100 * (V_peak - RMP) after the peak (APD90, APD50),
//                    placed within the step by the cubic through V and dV/dt at
//                    both ends when the integrator gives dV/dt (CVODE), else by
//                    the chord
//   max dV/dt        from the integrator's own steps: its dV/dt at step ends
//                    (CVODE), else the difference quotient over each step, taken
//                    at the step's middle; the activation time is refined to the
//                    vertex of the parabola through the largest sample and its
//                    neighbours on the steps either side
// A beat runs from one stimulus onset to the next (or to the end of the run);
// without stimulus the whole run is one beat.
//
// Whether a cell fired in a beat is decided once, here, and every measure
// downstream (means, conduction velocity, maps, block, capture) follows it:
// a cell fired when its potential rose at least firing_rise_mV(type) above
// the V it had at the beat's onset (APO - RMP). A myocyte must rise 20 mV (an
// action potential, not the electrotonic rise of a cell next to one; the
// criterion conduction velocity has always used). A fibroblast is not
// excitable: it "fires" when the wave drives it through its gap junctions,
// and its biomarkers then measure that response, as the seed paper's do; it
// must rise 1 mV (the paper's Fig. 3 tissues drive every fibroblast by 4.6 mV
// or more even at D_f 0.05 nS; a cell at rest drifts by thousandths). A cell
// that did not fire has no activation time, APO, APD or max dV/dt in that
// beat (NaN: empty fields in biomarkers.csv), only its RMP.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "io/checkpoint_file.hpp"
#include "measure/pre_upstroke_window.hpp"

#include "tissue/tissue.hpp"

namespace fibrodem {

// The rise above the onset V at which a cell counts as fired (above).
inline constexpr double kMyocyteFiringRise_mV = 20.0, kFibroblastFiringRise_mV = 1.0;
inline double firing_rise_mV(CellType type) {
  return type == CellType::myocyte ? kMyocyteFiringRise_mV : kFibroblastFiringRise_mV;
}

struct BeatBiomarkers {
  int cell = 0;
  CellType type = CellType::myocyte;
  int beat = 0;
  double activation_ms = 0, rmp_mV = 0, apo_mV = 0;
  double apd50_ms = std::numeric_limits<double>::quiet_NaN();
  double apd90_ms = std::numeric_limits<double>::quiet_NaN();
  double dvdt_max_mV_per_ms = 0;
};

// The order of biomarkers.csv and of a run's beats in one process: by beat,
// then cell.
inline bool in_beat_order(const BeatBiomarkers& a, const BeatBiomarkers& b) {
  return a.beat != b.beat ? a.beat < b.beat : a.cell < b.cell;
}

// Whether the cell fired in the beat (above): a fired beat has an activation time.
inline bool fired(const BeatBiomarkers& b) { return std::isfinite(b.activation_ms); }
// Whether it fired and rose as far as a myocyte's action potential: the cells
// that carry a wave, over which conduction velocity is fitted (a fibroblast
// driven less follows the front late, and would bend the fit).
inline bool carried_wave(const BeatBiomarkers& b) {
  return fired(b) && b.apo_mV - b.rmp_mV >= kMyocyteFiringRise_mV;
}

class BiomarkerTracker {
 public:
  // onsets: beat starts [ms]; beats starting before from_ms are not reported.
  BiomarkerTracker(std::vector<CellType> types, std::vector<double> onsets_ms, double from_ms,
                   std::function<void(const BeatBiomarkers&)> on_beat);

  // RMP as the mean V over window_ms ending gap_ms before each cell's
  // activation (output.biomarkers.rmp "pre_upstroke"); call before start().
  void use_pre_upstroke_rmp(double window_ms, double gap_ms);
  // The tissue's number of each tracked cell, reported as BeatBiomarkers::cell
  // (one number per type given, e.g. a rank's own cells in a run split over
  // MPI ranks); without it a cell's number is its index here. Call before start().
  void number_cells(std::vector<int> cell_numbers);

  void start(double t_ms, const double* V_mV);
  // One step from t_old to t_new; V at t_new per cell; dVdt at t_new or null.
  void step(double t_old_ms, double t_new_ms, const double* V_mV, const double* dVdt);
  // Whether the step to t_new may instead be taken range by range of cells
  // (step_cells, e.g. on several threads): no beat opens in it and no
  // pre-upstroke window is kept. Only for steps without the integrator's dV/dt.
  bool steps_by_range(double t_new_ms) const {
    return !pre_upstroke_ && !(next_onset_ < onsets_.size() && onsets_[next_onset_] < t_new_ms - 1e-9);
  }
  // step() for the cells [begin, end) only (ranges may be taken concurrently).
  void step_cells(double t_old_ms, double t_new_ms, const double* V_mV, std::size_t begin, std::size_t end);
  // Ends the last beat (call once at the end of the run).
  void finish();
  // Everything it holds between steps, for a checkpoint, and back (the
  // tracker must have been made for the same cells and onsets).
  void save(CheckpointFields& fields) const;
  void load(const CheckpointFields& fields);
  // The fields save() writes with one entry a tracked cell: rows of one
  // number a cell (row-major, value k * cells + c) and each cell's bytes,
  // which a run split over another number of ranks takes cell by cell
  // (run/checkpoint_recut.hpp). Those absent from a checkpoint are optional.
  static std::vector<std::string> per_cell_number_fields();
  static constexpr const char* kPerCellBytesField = "biomarkers.cells";

 private:
  // A cell's beat so far, beyond what the lanes' arrays hold (RMP, peak, max dV/dt).
  struct Cell {
    double t_act = 0;
    double cross50 = -1, cross90 = -1;
    // The last dV/dt sample (the integrator's at a step end, or a difference
    // quotient at a step's middle), its time, and the end of its step.
    // While max_pending, the last sample is the largest so far (dvdt_max_ at
    // t_act), taken on the step right after the sample these hold instead:
    // its left neighbour, kept until its right one refines the peak's time
    // (slope_step_end is the largest's step end).
    double slope_prev = std::numeric_limits<double>::quiet_NaN(), t_slope_prev = 0, slope_step_end = -1;
    std::uint8_t max_pending = 0;  // (a byte, not a bool: a checkpoint's bytes are all valid)
  };
  void open_beat(double onset, double t_old, double t_new, const double* V);
  void close_beat();
  // One cell over the step (the general path).
  void step_cell(std::size_t c, double t_old, double t_new, const double* V, const double* dVdt);
  // The step without the integrator's dV/dt, in SIMD lanes: most cells, most
  // steps, neither steepen, peak nor cross a repolarisation level; only those
  // that may take step_cell.
  void step_lanes(double t_old, double t_new, const double* V, std::size_t begin, std::size_t end);
  // Starts a cell's beat from its RMP (or V at the run's start).
  void reset_cell(std::size_t c, double rmp_mV);

  std::vector<std::uint8_t> types_;  // each cell's CellType, a byte each
  std::vector<int> cell_numbers_;  // empty: the index
  std::vector<double> onsets_;
  double from_ms_;
  std::function<void(const BeatBiomarkers&)> on_beat_;
  std::vector<Cell> cells_;
  // Per cell, in lanes' arrays (step_lanes reads them): V at the last step's
  // end, the beat's largest dV/dt, peak and RMP.
  std::vector<double> v_prev_, dvdt_max_, peak_, rmp_;
  // The integrator's dV/dt at the last step's end, per cell: sized at the
  // first step that gives it (empty: NaN for every cell).
  std::vector<double> dvdt_prev_;
  // With use_pre_upstroke_rmp: the window of V, and each cell's RMP from it
  // at its current max dV/dt.
  std::unique_ptr<PreUpstrokeWindow> pre_upstroke_;
  std::vector<double> rmp_pre_;
  int beat_ = -1;           // index of the open beat
  std::size_t next_onset_ = 0;
};

}  // namespace fibrodem
