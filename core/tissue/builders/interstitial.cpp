// `interstitial`: the seed paper's "interstitial fibroblast abundance"
// (section 2.2.2, Fig. 2b). Myocytes in vertical fibres, end to end (each one's
// bottom particle touching the top particle of the one below), each rotated by
// U(-max_rotation_deg, max_rotation_deg) and offset sideways by
// U(-max_offset_um, max_offset_um); the space is filled by random
// non-overlapping fibroblast particles of radius U(r_min, r_max) um
// (`fibroblast_radius_um`, paper [1, 4]), whose radii are then multiplied by
// U(1, growth_max) (paper 1.5). Particles that touch are bonded; fibroblast
// particles joined by bonds form one fibroblast.
//
// Decisions where the paper is silent (the paper relaxes its assembly with
// DEM cycles; a builder places things directly):
// - fibre axes `column_spacing_um` apart (default 24 um, about the in-series
//   23.57 um, so the tissue stays dense and ~1.16 mm wide); a rotated, offset
//   myocyte that would overlap a fibre already placed (by more than the
//   in-series lateral overlap, 1.43 um) is pushed right in 0.25 um steps, up to
//   12.5 um, as DEM relaxation would push it; failing that it is redrawn (30
//   times, the last straight); failing that the fibre restarts 16.7 um higher
//   (a small hole);
// - the fill is random sequential insertion, `fill_attempts_per_um2` attempts
//   per um^2 (default 0.07, the knob that sets the F-M ratio with the rotation,
//   offset and radii; PFC's `ball generate` count), below the median fibre top;
// - `growth`: `overlap` (default, the paper's literal rule: radii multiplied,
//   overlaps allowed, overlapping particles bonded; bonds start with a negative
//   gap, which the mechanics must take as the bond's reference) or `to_contact`
//   (a particle grows by its factor or until it touches its nearest neighbour);
// - a fibroblast is a connected set of bonded fill particles
//   (`max_fibroblast_particles` = 0, the paper's rule; > 0 splits bigger ones
//   into coupled cells, bonds taken in random order);
// - fill particles with no bond path to a myocyte are dropped, and so are the
//   rare cells cut off from the main body of tissue (a few myocytes at the
//   bottom edge whose fibre restarted after a blocked placement; seen in 4 of
//   40 seeds): the cell graph is connected. `keep_unconnected_fibroblasts`
//   keeps both.
// Defaults on 1.16 x 6.27 mm: ~2070 myocytes, F-M ~1.27 (the paper's example).
#include "tissue/builders/column_tissue.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

constexpr double kDefaultSpacing_um = 24.0;

}  // namespace

std::unique_ptr<TissueBuilder> make_interstitial_builder(JsonReader& tissue) {
  ColumnTissueSpec spec;
  spec.width_um = tissue.number("width_mm", 1.16, 0.05, 100) * 1000;
  spec.height_um = tissue.number("height_mm", 6.27, 0.125, 100) * 1000;
  spec.interstitial = read_interstitial_settings(tissue, InterstitialSettings{});
  const double spacing = tissue.number("column_spacing_um", kDefaultSpacing_um, kColumnPitch_um, 200);
  // Columns from the left edge, each one's protrusion kept inside the width.
  const double margin = min_interstitial_spacing_um(spec.interstitial) - kParticleRadius_um;
  for (double x = margin; x + margin <= spec.width_um + 1e-9; x += spacing)
    spec.column_x_um.push_back(x);
  if (spec.column_x_um.empty())
    throw ManifestError(tissue.path_of("width_mm"), "too narrow for one column of myocytes");
  spec.patch = Rect{0, spec.width_um, 0, spec.height_um};
  spec.patch_interstitial = true;
  spec.column_in_patch.assign(spec.column_x_um.size(), true);
  spec.fill_below_median_top = true;
  return std::make_unique<ColumnTissueBuilder>(std::move(spec));
}

}  // namespace fibrodem
