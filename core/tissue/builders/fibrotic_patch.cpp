// `fibrotic_patch`: the seed paper's plane-wave scene (section 3.3, Fig. 8): a
// 2.32 x 6.27 mm tissue of myocyte fibres (the in-series column layout, no
// fibroblasts outside the patch unless `fm_ratio` > 0) with a central
// rectangular fibrous region of ~930 fibroblasts, built with `arrangement`:
// - `in_series`: inside the patch each placed cell is a fibroblast with
//   probability `patch_fibroblast_fraction` (default 1: a solid block of
//   one-particle fibroblasts, the conduction block of Fig. 8a-g);
// - `interstitial`: every `column_stride`-th fibre (default 2, the ones not at
//   the patch's side edges) runs on through the patch with rotated, offset
//   myocytes chained end to end; the others stop below the patch and resume
//   above it; the patch's free space is filled with fibroblast particles as in
//   the `interstitial` builder (same keys), so myocyte coupling along the fibre
//   stays intact (Fig. 8h-m).
// The patch is `patch_width_mm` x `patch_height_mm`, centred at
// (`patch_centre_x_frac`, `patch_centre_y_frac`) of the tissue; the defaults
// (0.6 x 1.0 mm in-series, 0.9 x 1.4 mm interstitial) give ~930 fibroblasts
// with each arrangement (measured: 936; 860-930 by seed).
#include "tissue/builders/column_tissue.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
std::unique_ptr<TissueBuilder> make_fibrotic_patch_builder(JsonReader& tissue) {
  ColumnTissueSpec spec;
  spec.width_um = tissue.number("width_mm", 2.32, 0.1, 100) * 1000;
  spec.height_um = tissue.number("height_mm", 6.27, 0.25, 100) * 1000;
  const std::string arrangement = tissue.text("arrangement", std::nullopt, {"in_series", "interstitial"});
  spec.patch_interstitial = arrangement == "interstitial";
  const double fm = tissue.number("fm_ratio", 0.0, 0, 1000);
  spec.fibroblast_odds_outside = fm / (1 + fm);
  const double default_w = spec.patch_interstitial ? 0.9 : 0.6;
  const double default_h = spec.patch_interstitial ? 1.4 : 1.0;
  const double pw = tissue.number("patch_width_mm", default_w, 0.025, spec.width_um / 1000) * 1000;
  const double ph = tissue.number("patch_height_mm", default_h, 0.025, spec.height_um / 1000) * 1000;
  const double cx = tissue.number("patch_centre_x_frac", 0.5, 0, 1) * spec.width_um;
  const double cy = tissue.number("patch_centre_y_frac", 0.5, 0, 1) * spec.height_um;
  spec.patch = Rect{std::max(0.0, cx - pw / 2), std::min(spec.width_um, cx + pw / 2),
                    std::max(0.0, cy - ph / 2), std::min(spec.height_um, cy + ph / 2)};
  spec.column_x_um = in_series_columns(spec.width_um);
  if (!spec.patch_interstitial) {
    spec.fibroblast_odds_patch = tissue.number("patch_fibroblast_fraction", 1.0, 0, 1);
  } else {
    spec.interstitial = read_interstitial_settings(tissue, InterstitialSettings{});
    const int stride = static_cast<int>(tissue.integer("column_stride", 2, 2, 10));
    const double need = min_interstitial_spacing_um(spec.interstitial);
    if (stride * kColumnPitch_um < need - 1e-9)
      throw ManifestError(tissue.path_of("column_stride"),
                          "fibres " + std::to_string(stride * kColumnPitch_um) +
                              " um apart leave no room for the rotation and offset (need " +
                              std::to_string(need) + " um)");
    // Fibres through the patch: every stride-th of the columns inside it, never
    // the first or last one, so that rotated myocytes keep clear of the outside.
    std::vector<std::size_t> inside;
    for (std::size_t c = 0; c < spec.column_x_um.size(); ++c)
      if (spec.patch->contains_x(spec.column_x_um[c])) inside.push_back(c);
    spec.column_in_patch.assign(spec.column_x_um.size(), false);
    for (std::size_t k = 1; k + 1 < inside.size(); ++k)
      if (k % stride == 1 % stride) spec.column_in_patch[inside[k]] = true;
  }
  return std::make_unique<ColumnTissueBuilder>(std::move(spec));
}

}  // namespace fibrodem
