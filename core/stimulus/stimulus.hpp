// Periodic rectangular current pulses on sets of cells (seed paper eq. 1-2:
// whole-cell pA, positive = depolarising). A pulse k of a train is on for
// start + k*period <= t < start + k*period + duration.
#pragma once

#include <limits>
#include <vector>

#include "stimulus/stimulus_spec.hpp"
#include "tissue/cell_numbering.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct PulseTrain {
  std::vector<int> cells;
  double start_ms = 0, duration_ms = 0, amplitude_pA = 0, period_ms = 0;
  long long count = 1;
  // The cells its current goes into, in the held numbers of the per-cell
  // arrays: `cells` in one process; a rank's own of them split over ranks.
  std::vector<int> applied_to;

  bool on(double t_ms) const;
};

class Stimulus {
 public:
  Stimulus() = default;
  // Resolves each train's target on the tissue; a target naming no cell (or a
  // cell index out of range) is a ManifestError at the stimulus' path.
  Stimulus(const std::vector<StimulusSpec>& specs, const Tissue& tissue);

  // Adds the stimulus current at time t into i_ext (indexed by held cell:
  // by tissue cell in one process).
  void add_current(double t_ms, double* i_ext_pA) const;
  // Sets i_ext back to 0 wherever add_current adds: a pulse's current
  // undone in as many writes as it took.
  void clear_current(double* i_ext_pA) const;
  // A rank of a split run applies the current to its own cells alone,
  // under their numbers in `numbering` (tissue/cell_numbering.hpp), so that
  // a pulse costs it its own cells; trains() still lists every cell
  // stimulated, by tissue number.
  void hold_only(const CellNumbering& numbering);
  // Whether any pulse is on at t.
  bool on(double t_ms) const;
  // The first pulse edge (on or off) strictly after t, or +inf.
  double next_edge_after(double t_ms) const;
  // Sorted, distinct pulse onsets in [0, until]: they start the beats.
  std::vector<double> onsets(double until_ms) const;
  double shortest_pulse_ms() const;
  const std::vector<PulseTrain>& trains() const { return trains_; }

 private:
  std::vector<PulseTrain> trains_;
};

// Times closer than this [ms] are the same instant (guards n*dt round-off).
inline constexpr double kTimeEpsilon_ms = 1e-9;

}  // namespace fibrodem
