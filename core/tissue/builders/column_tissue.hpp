// The procedural generator behind the seed paper's tissues (section 2.2.2):
// cells placed bottom to top in vertical columns (fibres along y), with an
// optional rectangular patch that is built in-series (cells drawn fibroblast
// with other odds) or interstitially (myocytes rotated and offset, the space
// around them filled with small fibroblast particles). Used by the `in_series`,
// `interstitial` and `fibrotic_patch` builders.
//
// Geometry (decisions where the paper is silent, see each builder's notes):
// - columns are kColumnPitch_um = sqrt((2r)^2 - (d/2)^2) = 23.57 um apart, so
//   that every particle of a myocyte touches or slightly overlaps (<= 1.43 um)
//   a particle of the neighbouring column's myocyte; along a column cells touch
//   end to end (pitch 125 um for a myocyte, 25 um for a fibroblast particle);
// - a bond joins two particles of different cells whose centres are no farther
//   apart than the sum of their radii (+ 0.1 % tolerance): touching or
//   overlapping. Overlapping bonded pairs start with a gap < 0 (the mechanics
//   should take each bond's initial gap as its reference).
#pragma once

#include "tissue/tissue_builder.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "util/json_reader.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// A constant expression, so that constants derived from it elsewhere are
// never read before it is set (namespace-scope initialisation order).
inline constexpr double kColumnPitch_um = [] {
  const double square = 4 * kParticleRadius_um * kParticleRadius_um - kParticleSpacing_um * kParticleSpacing_um / 4;
  double root = square;  // Newton's iteration for sqrt: std::sqrt is not constexpr
  for (int i = 0; i < 60; ++i) root = (root + square / root) / 2;
  return root;
}();
// Largest overlap allowed between particles of two cells placed by the column
// generator (the in-series lateral overlap); fibroblast fill particles never overlap.
inline constexpr double kAllowedOverlap_um = 2 * kParticleRadius_um - kColumnPitch_um + 1e-9;
// Relative tolerance under which two particles count as touching.
inline constexpr double kTouchTolerance = 1e-3;
// Whether two particles touch or overlap (within kTouchTolerance of their
// radii's sum): where the builders put a bond.
inline bool touching(const Particle& p, const Particle& q) {
  const double reach = (p.r_um + q.r_um) * (1 + kTouchTolerance);
  const double dx = q.x_um - p.x_um, dy = q.y_um - p.y_um;
  return dx * dx + dy * dy <= reach * reach;
}

struct Rect {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool contains_x(double x) const { return x >= x0 && x <= x1; }
  bool contains_y(double y) const { return y >= y0 && y < y1; }
};

struct InterstitialSettings {
  double max_angle_rad = 10.0 * M_PI / 180.0;  // myocyte rotation U(-a, a)
  double max_offset_um = 2.0;                  // horizontal offset U(-h, h)
  double r_min_um = 1.0, r_max_um = 4.0;       // fibroblast particles drawn U(r_min, r_max)
  double growth_max = 1.5;                     // then radii times U(1, growth_max)
  bool growth_overlaps = true;                 // grow regardless of neighbours (else up to contact)
  double fill_attempts_per_um2 = 0.07;         // random insertion attempts per um^2 of patch
  int max_fibroblast_particles = 0;            // largest fibroblast (bonded particles); 0: no limit
  bool drop_unconnected = true;                // drop fibroblasts not connected to any myocyte
};

struct ColumnTissueSpec {
  double width_um = 0, height_um = 0;
  std::vector<double> column_x_um;     // the columns' axes
  double fibroblast_odds_outside = 0;  // probability that a cell placed outside the patch is a fibroblast
  std::optional<Rect> patch;
  bool patch_interstitial = false;
  double fibroblast_odds_patch = 0;    // in-series patch
  std::vector<bool> column_in_patch;   // interstitial patch: the column's fibre runs through it
  bool fill_below_median_top = false;  // fill only up to the median column top (not the ragged top)
  InterstitialSettings interstitial;
};

Tissue build_column_tissue(const ColumnTissueSpec& spec, std::uint64_t seed);

// The builder of every column tissue (in_series, interstitial, fibrotic_patch):
// they differ only in the spec their factories read.
class ColumnTissueBuilder final : public TissueBuilder {
 public:
  explicit ColumnTissueBuilder(ColumnTissueSpec spec) : spec_(std::move(spec)) {}
  Tissue build(std::uint64_t seed) const override { return build_column_tissue(spec_, seed); }

 private:
  ColumnTissueSpec spec_;
};

// Column axes at kColumnPitch_um from x = r, as many as fit in the width.
std::vector<double> in_series_columns(double width_um);

// Reads the interstitial settings (keys `max_rotation_deg`, `max_offset_um`,
// `fibroblast_radius_um` [min, max], `growth_max`, `fill_attempts_per_um2`,
// `max_fibroblast_particles`, `keep_unconnected_fibroblasts`) with the given defaults.
InterstitialSettings read_interstitial_settings(JsonReader& reader,
                                                const InterstitialSettings& defaults);
// Smallest column spacing at which a straight myocyte never overlaps a rotated,
// offset neighbour: 2r + 50 um sin(max angle) + max offset.
double min_interstitial_spacing_um(const InterstitialSettings& s);

}  // namespace fibrodem
