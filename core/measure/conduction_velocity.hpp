// Conduction velocity along the fibre (docs/reference/outputs.md#biomarkers;
// docs/reference/references.md#measurement-conventions): a least-squares fit of activation time against distance from the
// stimulated cells, CV = 1/slope. It is robust to the stair-stepped activation
// times of a discrete tissue. Cells in the stimulated region, within a margin of
// it, or within a margin of the far edge are left out (the wave is not yet, or
// no longer, plane there), and so are cells that did not activate.
#pragma once

#include <optional>
#include <vector>

namespace fibrodem {

struct ConductionSample {
  double position_um = 0;  // along the fibre
  double activation_ms = 0;
  bool stimulated = false;
  bool activated = false;
};

struct ConductionFit {
  double cv_cm_per_s = 0;
  double r_squared = 0;
  int cells_used = 0;
  double from_um = 0, to_um = 0;  // the window of distances fitted
};

// margin_fraction: share of the unstimulated length left out at each end.
std::optional<ConductionFit> fit_conduction_velocity(const std::vector<ConductionSample>& cells,
                                                     double margin_fraction = 0.1,
                                                     int minimum_cells = 5);

// End-to-end transit (output.biomarkers.cv "transit"): over the same window as
// the fit, the distance between the mean positions of the cells in its first
// and its last band_fraction of the length, divided by the difference of their
// mean activation times. It weighs the whole path's slow stretches as a wave
// arriving late does (a fit weighs every cell alike); r_squared is NaN.
std::optional<ConductionFit> transit_conduction_velocity(const std::vector<ConductionSample>& cells,
                                                         double margin_fraction = 0.1,
                                                         double band_fraction = 0.05);

}  // namespace fibrodem
