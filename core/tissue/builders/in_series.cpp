// `in_series`: the seed paper's "random fibroblast insertion in series"
// (section 2.2.2, Fig. 2a): cells generated bottom to top in vertical columns
// (fibres along y); each placed cell is a fibroblast with probability
// fm_ratio / (1 + fm_ratio), so that fibroblasts : myocytes -> fm_ratio, else a
// 7-particle myocyte (125 x 25 um). A fibroblast (the paper's "group of
// fibroblasts") is one particle of radius 12.5 um.
//
// Decisions where the paper is silent: columns 23.57 um apart
// (sqrt(25^2 - 8.33^2): every myocyte particle touches or overlaps by at most
// 1.43 um a particle of the next column, so neighbouring fibres are bonded all
// along; with this spacing the paper's 1.16 x 6.27 mm tissue at F-M 0.41 holds
// ~3200 cells, as its 2289 + 936); no stagger other than the one the random
// cell types make; every column starts at y = 0 and stops at the last cell that
// fits under the height. Parameters: width_mm, height_mm, fm_ratio.
#include "tissue/builders/column_tissue.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
std::unique_ptr<TissueBuilder> make_in_series_builder(JsonReader& tissue) {
  ColumnTissueSpec spec;
  spec.width_um = tissue.number("width_mm", 1.16, 0.025, 100) * 1000;
  spec.height_um = tissue.number("height_mm", 6.27, 0.125, 100) * 1000;
  const double fm = tissue.number("fm_ratio", 0.41, 0, 1000);
  spec.column_x_um = in_series_columns(spec.width_um);
  spec.fibroblast_odds_outside = fm / (1 + fm);
  return std::make_unique<ColumnTissueBuilder>(std::move(spec));
}

}  // namespace fibrodem
