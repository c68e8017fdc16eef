// Fibrosis patterns on a regular grid of cell slots: which slots are fibrotic.
//
// The four patterns of the histological classification used in atrial and
// ventricular modelling (de Jong et al. 2011 J Cardiovasc Transl Res 4:41;
// Nguyen, Qu, Weiss 2014 J Mol Cell Cardiol 70:83; Kazbanov, ten Tusscher,
// Panfilov 2016 Sci Rep 6:20835):
// - diffuse: every slot fibrotic independently with probability `density`;
// - patchy: Gaussian-filtered white noise thresholded so that exactly
//   round(density * slots) slots (those of highest value) are fibrotic, giving
//   patches of the requested correlation length;
// - interstitial: thin lines along the fibres (a column's consecutive slots,
//   `line_length_um` long) dropped at random until the density is reached;
// - compact: one solid rectangle of area density * sheet area, of the
//   requested aspect, centred where asked (clipped at the sheet's edges).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tissue/particle_grid.hpp"

namespace fibrodem {

enum class FibrosisPattern { diffuse, patchy, interstitial, compact };

// Slot (c, r) of a sheet: column c (across the fibres, x), row r (along them, y).
// Columns are `pitch_x_um` apart; odd columns are shifted half a cell along y,
// so that the cells make a brick wall (each cell beside two of each neighbouring column).
struct SheetGrid {
  int columns = 0, rows = 0;
  double pitch_x_um = 0, pitch_y_um = 0;
  std::size_t slots() const { return static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows); }
  std::size_t slot(int c, int r) const { return static_cast<std::size_t>(c) * rows + r; }
  double x_um(int c) const { return (c + 0.5) * pitch_x_um; }
  double y_um(int c, int r) const { return (r + 0.5 + 0.5 * (c % 2)) * pitch_y_um; }
  double width_um() const { return columns * pitch_x_um; }
  double length_um() const { return (rows + (columns > 1 ? 0.5 : 0.0)) * pitch_y_um; }
};

struct FibrosisSpec {
  double density = 0;  // fraction of slots, [0, 1)
  FibrosisPattern pattern = FibrosisPattern::diffuse;
  double correlation_length_um = 500;  // patchy: lag at which the field's autocorrelation is 1/e
  double line_length_um = 500;         // interstitial: length of one line along the fibre
  double centre_x_frac = 0.5, centre_y_frac = 0.5;  // compact: centre of the region
  double aspect = 1;                                // compact: length (y) / width (x) of the region
};

// One byte per slot (1: fibrotic), deterministic for the random stream.
std::vector<char> fibrotic_slots(const SheetGrid& grid, const FibrosisSpec& spec, BuilderRandom& rng);

FibrosisPattern fibrosis_pattern_from_name(const std::string& name);  // one of the names below
inline const std::vector<std::string> kFibrosisPatternNames = {"diffuse", "patchy", "interstitial", "compact"};

}  // namespace fibrodem
