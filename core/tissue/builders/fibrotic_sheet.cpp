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
//   transverse connections). `fibrosis.collagen` says what the holes are
//   mechanically: `voids` (default: empty) or `particles` (passive collagen
//   particles). Septa stay mechanically, as bonds through collagen (collagen
//   insulates but transmits force; and the side neighbours overlap by 1.06
//   um, so without a bond they would push apart as unbonded contacts).
//   Collagen particles and septa take mechanics.collagen_stiffness_factor.
//
// Bonds (the DEM body, and the cell graph: two cells are coupled where a bond
// joins them) as the column tissues make them (column_tissue.hpp): every pair
// of touching particles of two neighbouring slots. A myocyte is the paper's 7
// particles; on this layout each touches 3 particles of each side neighbour
// (centres 23.94 um apart, 1.06 um overlap) and its end particle the next
// cell's (25 um apart). A fibrotic slot's fibroblast or collagen is the same 7
// disks, each a body of its own bonded to the next: a fibroblast particle of
// the in-series layout's size (r 12.5 um) at a myocyte's spacing, so that it
// touches its neighbours as a myocyte would (a single disk in the 125 um slot
// would touch none). So the bonds give exactly the brick wall's cell graph.
// The seed paper's Fig. 8 patch (`fibrotic_patch`, in-series arrangement) is
// the compact pattern as fibroblasts: density = patch area / tissue area
// (0.6 x 1.0 mm in 2.32 x 6.27 mm: 0.0413), aspect = 1.0 / 0.6, centred; that
// builder stays for the paper's particle geometry (one-particle fibroblasts
// 25 um tall, so ~930 of them, against ~40 brick slots here).
#include <cmath>
#include <stdexcept>

#include "tissue/builders/column_tissue.hpp"
#include "tissue/fibrosis_pattern.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

enum class FibrosisAs { fibroblasts, collagen };
enum class CollagenAs { voids, particles };

// The particles of one slot: [first, first + count) of the tissue's
// particles, or of its collagen particles.
struct SlotParticles {
  int first = 0, count = 0;
  bool collagen = false;
};

// The 7 disks of a myocyte's geometry along a fibrotic slot centred at (x, y),
// as a fibroblast cell's particles or as collagen particles.
SlotParticles add_slot_disks(Tissue& tissue, double x, double y, bool collagen) {
  SlotParticles s;
  s.collagen = collagen;
  const int cell = collagen ? -1 : tissue.add_cell(CellType::fibroblast, x, y);
  for (int k = 0; k < kMyocyteParticles; ++k) {
    const double py = y - kMyocyteEndOffset_um + k * kParticleSpacing_um;
    const int id = collagen ? tissue.add_collagen_particle(x, py, kParticleRadius_um)
                            : tissue.add_particle(cell, x, py, kParticleRadius_um);
    if (k == 0) s.first = id;
  }
  s.count = kMyocyteParticles;
  return s;
}

class FibroticSheetBuilder final : public TissueBuilder {
 public:
  FibroticSheetBuilder(SheetGrid grid, FibrosisSpec fibrosis, FibrosisAs as, CollagenAs collagen)
      : grid_(grid), fibrosis_(fibrosis), as_(as), collagen_(collagen) {}

  Tissue build(std::uint64_t seed) const override {
    BuilderRandom rng(seed);
    const std::vector<char> fibrotic = fibrotic_slots(grid_, fibrosis_, rng);
    const bool septa = as_ == FibrosisAs::collagen && fibrosis_.pattern == FibrosisPattern::interstitial;
    const bool holes = as_ == FibrosisAs::collagen && !septa;
    const bool particles = collagen_ == CollagenAs::particles;
    Tissue tissue;
    std::vector<SlotParticles> slot(grid_.slots());
    tissue.type.reserve(grid_.slots());
    tissue.x_um.reserve(grid_.slots());
    tissue.y_um.reserve(grid_.slots());
    tissue.particles.reserve(kMyocyteParticles * grid_.slots());
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        const double x = grid_.x_um(c), y = grid_.y_um(c, r);
        if (holes && fibrotic[s]) {
          if (particles) slot[s] = add_slot_disks(tissue, x, y, true);
        } else if (fibrotic[s] && !septa) {
          slot[s] = add_slot_disks(tissue, x, y, false);
        } else {
          slot[s] = {static_cast<int>(tissue.particles.size()), kMyocyteParticles, false};
          add_vertical_myocyte(tissue, x, y - kMyocyteLength_um / 2);
        }
      }
    const int cell_particles = static_cast<int>(tissue.particles.size());
    tissue.bonds.reserve(7 * grid_.slots());  // a slot: 1 to the next up, 3 to each of 2 in the next column
    auto index = [&](const SlotParticles& s, int k) { return (s.collagen ? cell_particles : 0) + s.first + k; };
    auto at = [&](const SlotParticles& s, int k) -> const Particle& {
      return s.collagen ? tissue.collagen[s.first + k] : tissue.particles[s.first + k];
    };
    // Bonds inside a slot of disks: each to the next (16.67 um apart).
    for (const SlotParticles& s : slot)
      if (s.count > 0 && (s.collagen || tissue.type[tissue.particles[s.first].cell] == CellType::fibroblast))
        for (int k = 0; k + 1 < s.count; ++k) {
          if (s.collagen) tissue.add_collagen_bond(index(s, k), index(s, k + 1));
          else tissue.add_bond(index(s, k), index(s, k + 1));
        }
    // Between neighbouring slots: every touching pair; through collagen where
    // either slot is collagen or a septum lies between them (no coupling).
    auto bond = [&](std::size_t a, std::size_t b, bool septum) {
      const SlotParticles &sa = slot[a], &sb = slot[b];
      if (sa.count == 0 || sb.count == 0) return;
      const bool through_collagen = septum || sa.collagen || sb.collagen;
      int made = 0;
      for (int i = 0; i < sa.count; ++i)
        for (int j = 0; j < sb.count; ++j) {
          if (!touching(at(sa, i), at(sb, j))) continue;
          if (through_collagen) tissue.add_collagen_bond(index(sa, i), index(sb, j));
          else tissue.add_bond(index(sa, i), index(sb, j));
          ++made;
        }
      if (made == 0) throw std::logic_error("fibrotic_sheet: neighbouring slots whose particles do not touch");
    };
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        if (r + 1 < grid_.rows) bond(s, grid_.slot(c, r + 1), false);
        if (c + 1 == grid_.columns) continue;
        // Beside cell r of an even column: rows r - 1 and r of the (shifted)
        // odd column; of an odd column: rows r and r + 1 of the even one.
        const int first = c % 2 == 0 ? r - 1 : r;
        for (int rn = first; rn <= first + 1; ++rn) {
          if (rn < 0 || rn >= grid_.rows) continue;
          const std::size_t n = grid_.slot(c + 1, rn);
          bond(s, n, septa && (fibrotic[s] || fibrotic[n]));
        }
      }
    tissue.finalise();
    return tissue;
  }

 private:
  SheetGrid grid_;
  FibrosisSpec fibrosis_;
  FibrosisAs as_;
  CollagenAs collagen_;
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

FibrosisSpec read_fibrosis(JsonReader& f, FibrosisAs* as, CollagenAs* collagen) {
  FibrosisSpec spec;
  spec.density = f.number("density", std::nullopt, 0, 1);
  if (spec.density >= 1)
    throw ManifestError(f.path_of("density"), "expected a fraction of cells in [0, 1), got " + describe_json(spec.density));
  spec.pattern = fibrosis_pattern_from_name(f.text("pattern", std::nullopt, kFibrosisPatternNames));
  *as = f.text("as", std::string("collagen"), {"fibroblasts", "collagen"}) == "fibroblasts" ? FibrosisAs::fibroblasts
                                                                                         : FibrosisAs::collagen;
  *collagen = f.text("collagen", std::string("voids"), {"voids", "particles"}) == "particles" ? CollagenAs::particles
                                                                                           : CollagenAs::voids;
  if (*collagen == CollagenAs::particles && *as != FibrosisAs::collagen)
    throw ManifestError(f.path_of("collagen"), "collagen particles need `as: collagen`, got `as: fibroblasts`");
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
  CollagenAs collagen = CollagenAs::voids;
  if (tissue.has("fibrosis")) {
    JsonReader f = tissue.object("fibrosis");
    fibrosis = read_fibrosis(f, &as, &collagen);
  }
  return std::make_unique<FibroticSheetBuilder>(grid, fibrosis, as, collagen);
}

}  // namespace fibrodem
