// `fibrotic_sheet`: a large 2D sheet of myocytes on a regular brick layout,
// with fibrosis of a given density and pattern (tissue/fibrosis_pattern.hpp:
// diffuse, patchy, interstitial, compact), for arrhythmia studies.
//
// Layout: fibres along y. Cells are 125 um long (the seed paper's myocyte);
// columns are 23.57 um apart (the in-series pitch, column_tissue.hpp); odd
// columns are shifted by half a cell, so every cell is coupled end to end to
// the cells above and below it and side to side to the two cells beside it in
// each neighbouring column (6 neighbours, the brick wall of discrete atrial
// models). The sheet holds as many whole cells as fit in width_mm x length_mm.
//
// Fibrosis (`fibrosis.as`):
// - `fibroblasts`: fibrotic slots hold fibroblasts, coupled to their
//   neighbours as any cell (coupling.D_f_nS);
// - `collagen`: fibrotic slots hold no cell (non-conducting collagen: the
//   holes carry no current); for the interstitial pattern the cells stay and
//   the collagen septa cut their side-to-side couplings instead (de Jong et
//   al. 2011; Kazbanov et al. 2016: interstitial fibrosis as removed
//   transverse connections).
//
// The cells get the paper's particles (7 per myocyte, one per fibroblast) for
// the pictures and VTK files, but no bonds: the builder makes the cell graph,
// not a DEM body (mechanics is refused, mechanics/dem_bodies.cpp), so it serves
// electrophysiology.
// The seed paper's Fig. 8 patch (`fibrotic_patch`, in-series arrangement) is
// the compact pattern as fibroblasts: density = patch area / tissue area
// (0.6 x 1.0 mm in 2.32 x 6.27 mm: 0.0413), aspect = 1.0 / 0.6, centred; that
// builder stays for the paper's particle geometry (one-particle fibroblasts
// 25 um tall, so ~930 of them, against ~40 brick slots here).
#include <cmath>

#include "tissue/builders/column_tissue.hpp"
#include "tissue/fibrosis_pattern.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

enum class FibrosisAs { fibroblasts, collagen };

class FibroticSheetBuilder final : public TissueBuilder {
 public:
  FibroticSheetBuilder(SheetGrid grid, FibrosisSpec fibrosis, FibrosisAs as)
      : grid_(grid), fibrosis_(fibrosis), as_(as) {}

  Tissue build(std::uint64_t seed) const override {
    BuilderRandom rng(seed);
    const std::vector<char> fibrotic = fibrotic_slots(grid_, fibrosis_, rng);
    const bool septa = as_ == FibrosisAs::collagen && fibrosis_.pattern == FibrosisPattern::interstitial;
    const bool holes = as_ == FibrosisAs::collagen && !septa;
    Tissue tissue;
    std::vector<int> cell_of(grid_.slots(), -1);
    tissue.type.reserve(grid_.slots());
    tissue.x_um.reserve(grid_.slots());
    tissue.y_um.reserve(grid_.slots());
    tissue.particles.reserve(kMyocyteParticles * grid_.slots());
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        if (holes && fibrotic[s]) continue;
        const double x = grid_.x_um(c), y = grid_.y_um(c, r);
        cell_of[s] = fibrotic[s] && !septa ? add_round_fibroblast(tissue, x, y)
                                            : add_vertical_myocyte(tissue, x, y - kMyocyteLength_um / 2);
      }
    // Edges in increasing (i, j): cells are numbered column by column, bottom
    // to top, so the cell above and those of the next column come later.
    tissue.cell_edges.reserve(3 * tissue.cell_count());
    auto couple = [&](std::size_t a, std::size_t b) {
      if (cell_of[a] >= 0 && cell_of[b] >= 0) tissue.cell_edges.emplace_back(cell_of[a], cell_of[b]);
    };
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        if (r + 1 < grid_.rows) couple(s, grid_.slot(c, r + 1));
        if (c + 1 == grid_.columns) continue;
        // Beside cell r of an even column: rows r - 1 and r of the (shifted)
        // odd column; of an odd column: rows r and r + 1 of the even one.
        const int first = c % 2 == 0 ? r - 1 : r;
        for (int rn = first; rn <= first + 1; ++rn) {
          if (rn < 0 || rn >= grid_.rows) continue;
          const std::size_t n = grid_.slot(c + 1, rn);
          if (septa && (fibrotic[s] || fibrotic[n])) continue;
          couple(s, n);
        }
      }
    tissue.finalise();
    return tissue;
  }

 private:
  SheetGrid grid_;
  FibrosisSpec fibrosis_;
  FibrosisAs as_;
};

SheetGrid read_sheet_grid(JsonReader& tissue) {
  SheetGrid grid;
  grid.pitch_x_um = kColumnPitch_um;
  grid.pitch_y_um = kMyocyteLength_um;
  const double width_um = tissue.number("width_mm", std::nullopt, 0.025, 100) * 1000;
  const double length_um = tissue.number("length_mm", std::nullopt, 0.25, 100) * 1000;
  grid.columns = std::max(1, static_cast<int>(std::floor(width_um / grid.pitch_x_um + 1e-9)));
  // With more than one column, odd columns start half a cell up.
  const double usable_um = grid.columns > 1 ? length_um - grid.pitch_y_um / 2 : length_um;
  grid.rows = std::max(1, static_cast<int>(std::floor(usable_um / grid.pitch_y_um + 1e-9)));
  return grid;
}

FibrosisSpec read_fibrosis(JsonReader& f, FibrosisAs* as) {
  FibrosisSpec spec;
  spec.density = f.number("density", std::nullopt, 0, 1);
  if (spec.density >= 1)
    throw ManifestError(f.path_of("density"), "expected a fraction of cells in [0, 1), got " + describe_json(spec.density));
  spec.pattern = fibrosis_pattern_from_name(f.text("pattern", std::nullopt, kFibrosisPatternNames));
  *as = f.text("as", std::string("collagen"), {"fibroblasts", "collagen"}) == "fibroblasts" ? FibrosisAs::fibroblasts
                                                                                         : FibrosisAs::collagen;
  switch (spec.pattern) {
    case FibrosisPattern::patchy:
      spec.correlation_length_um = f.number("correlation_length_mm", 0.5, 0.01, 20) * 1000;
      break;
    case FibrosisPattern::interstitial:
      spec.line_length_um = f.number("line_length_mm", 0.5, 0.125, 20) * 1000;
      break;
    case FibrosisPattern::compact:
      spec.centre_x_frac = f.number("centre_x_frac", 0.5, 0, 1);
      spec.centre_y_frac = f.number("centre_y_frac", 0.5, 0, 1);
      spec.aspect = f.number("aspect", 1.0, 0.01, 100);
      break;
    case FibrosisPattern::diffuse:
      break;
  }
  f.finish();
  return spec;
}

}  // namespace

std::unique_ptr<TissueBuilder> make_fibrotic_sheet_builder(JsonReader& tissue) {
  const SheetGrid grid = read_sheet_grid(tissue);
  FibrosisSpec fibrosis;
  FibrosisAs as = FibrosisAs::collagen;
  if (tissue.has("fibrosis")) {
    JsonReader f = tissue.object("fibrosis");
    fibrosis = read_fibrosis(f, &as);
  }
  return std::make_unique<FibroticSheetBuilder>(grid, fibrosis, as);
}

}  // namespace fibrodem
