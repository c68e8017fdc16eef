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
//
// A rank of a run split over MPI ranks without mechanics takes the cells
// alone (build_cells: the same cells and graph, without the particles and
// bonds, ~40 of the ~330 bytes a cell), and rank 0 the particles one by one
// for their imprint (for_each_particle): no rank holds the whole tissue's
// particles; a rank other than 0 takes them one at a time from the slots
// (stream_cells), keeping the centres of its own cells and ghosts alone
// (docs/guide/parallel.md).
#include <array>
#include <cmath>
#include <stdexcept>

#include "tissue/builders/column_tissue.hpp"
#include "tissue/fibrosis_pattern.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

enum class FibrosisAs { fibroblasts, collagen };
enum class CollagenAs { voids, particles };

// What a slot holds: a myocyte, a fibroblast or collagen disks, or nothing
// (a collagen void).
enum class SlotKind : char { myocyte, fibroblast, collagen, empty };

using SlotDisks = std::array<Particle, kMyocyteParticles>;

// A myocyte's disks along its axis from its centre (add_myocyte's).
constexpr std::array<double, kMyocyteParticles> kMyocyteDiskOffset_um = [] {
  std::array<double, kMyocyteParticles> a{};
  for (int k = 0; k < kMyocyteParticles; ++k) a[k] = -kMyocyteEndOffset_um + k * kParticleSpacing_um;
  return a;
}();

// The sheet's slots for a seed: what each holds, its disks, and the
// junctions between neighbouring slots. build() and build_cells() both read
// it, so that they make the same cells, in the same order, and one graph.
class SheetSlots {
 public:
  SheetSlots(const SheetGrid& grid, const FibrosisSpec& fibrosis, FibrosisAs as, CollagenAs collagen,
             std::uint64_t seed)
      : grid_(grid) {
    BuilderRandom rng(seed);
    fibrotic_ = fibrotic_slots(grid, fibrosis, rng);
    septa_ = as == FibrosisAs::collagen && fibrosis.pattern == FibrosisPattern::interstitial;
    holes_ = as == FibrosisAs::collagen && !septa_;
    collagen_particles_ = collagen == CollagenAs::particles;
  }

  SlotKind kind(std::size_t s) const {
    if (!fibrotic_[s] || septa_) return SlotKind::myocyte;
    if (!holes_) return SlotKind::fibroblast;
    return collagen_particles_ ? SlotKind::collagen : SlotKind::empty;
  }
  // Whether a slot holds a cell (a myocyte or a fibroblast), which the
  // cells are numbered by, slot after slot.
  static bool holds_cell(SlotKind kind) { return kind == SlotKind::myocyte || kind == SlotKind::fibroblast; }
  // Whether a slot's disks are separate bodies, each bonded to the next (a
  // fibroblast's, collagen's), not one myocyte's clump.
  static bool chained(SlotKind kind) { return kind == SlotKind::fibroblast || kind == SlotKind::collagen; }

  // Each slot (c, r), column by column, with what it holds.
  template <class Visit>
  void for_each_slot(Visit&& visit) const {
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        visit(c, r, s, kind(s));
      }
  }

  // The centre of the cell in slot (c, r), and its 7 disks bottom to top, of
  // cell `cell` (-1 for collagen). A myocyte's are add_vertical_myocyte's (its
  // arithmetic, so the same bits); a fibrotic slot's are a myocyte's spacing
  // along the slot's centre line.
  std::array<double, 2> centre_um(int c, int r, SlotKind kind) const {
    const double x = grid_.x_um(c), y = grid_.y_um(c, r);
    return {x, kind == SlotKind::myocyte ? y - kMyocyteLength_um / 2 + kMyocyteLength_um / 2 : y};
  }
  // (Rounded one way whatever the compiler contracts, so that every build
  // of fibrodem makes the same tissue: a myocyte's offsets from its centre
  // are constants, a fibrotic slot's disks one fused multiply-add each.)
  SlotDisks disks(int c, int r, SlotKind kind, int cell) const {
    const auto [x, y] = centre_um(c, r, kind);
    SlotDisks d;
    for (int k = 0; k < kMyocyteParticles; ++k)
      d[k] = {x,
              kind == SlotKind::myocyte ? y + kMyocyteDiskOffset_um[k]
                                        : std::fma(k, kParticleSpacing_um, y - kMyocyteEndOffset_um),
              kParticleRadius_um, cell};
    return d;
  }

  // Each junction between two slots that hold disks, in the order the
  // bonds are made: a slot's next up its column, then the two beside it in
  // the next column (beside cell r of an even column: rows r - 1 and r of
  // the shifted odd column; of an odd column: rows r and r + 1 of the even
  // one). visit(a, b, septum): slots a and b, with an interstitial septum
  // between them or not.
  template <class Visit>
  void for_each_junction(Visit&& visit) const {
    auto join = [&](std::size_t a, std::size_t b, bool septum) {
      if (kind(a) != SlotKind::empty && kind(b) != SlotKind::empty) visit(a, b, septum);
    };
    for (int c = 0; c < grid_.columns; ++c)
      for (int r = 0; r < grid_.rows; ++r) {
        const std::size_t s = grid_.slot(c, r);
        if (r + 1 < grid_.rows) join(s, grid_.slot(c, r + 1), false);
        if (c + 1 == grid_.columns) continue;
        const int first = c % 2 == 0 ? r - 1 : r;
        for (int rn = first; rn <= first + 1; ++rn) {
          if (rn < 0 || rn >= grid_.rows) continue;
          const std::size_t n = grid_.slot(c + 1, rn);
          join(s, n, septa_ && (fibrotic_[s] || fibrotic_[n]));
        }
      }
  }

  // The centre of the cell in slot s, numbered `cell`.
  CellCentre centre_of(std::size_t s, int cell) const {
    const auto [c, r] = column_row(s);
    const auto [x, y] = centre_um(c, r, kind(s));
    return {cell, x, y};
  }

  // The touching pairs (i, j) of slot a's and slot b's disks, each handed
  // to bond(i, j); returns how many. Neighbouring slots always touch.
  template <class Bond>
  int touching_pairs(std::size_t a, std::size_t b, Bond&& bond) const {
    const SlotDisks da = disks_of(a), db = disks_of(b);
    int made = 0;
    for (int i = 0; i < kMyocyteParticles; ++i)
      for (int j = 0; j < kMyocyteParticles; ++j)
        if (touching(da[i], db[j])) {
          bond(i, j);
          ++made;
        }
    if (made == 0) throw std::logic_error("fibrotic_sheet: neighbouring slots whose particles do not touch");
    return made;
  }

 private:
  std::array<int, 2> column_row(std::size_t s) const {
    const auto rows = static_cast<std::size_t>(grid_.rows);
    return {static_cast<int>(s / rows), static_cast<int>(s % rows)};
  }
  SlotDisks disks_of(std::size_t s) const {
    const auto [c, r] = column_row(s);
    return disks(c, r, kind(s), -1);
  }

  SheetGrid grid_;
  std::vector<char> fibrotic_;
  bool septa_ = false, holes_ = false, collagen_particles_ = false;
};

// The cell numbers of two neighbouring columns' slots (-1: no cell), as
// the cells are numbered, slot after slot, moved along as the junctions
// go column by column (for_each_junction: slot a's column never goes back,
// slot b's is a's or the next): no map of every slot's cell is held.
class ColumnCellNumbers {
 public:
  ColumnCellNumbers(const SheetSlots& sheet, const SheetGrid& grid)
      : sheet_(sheet), grid_(grid), numbers_{std::vector<int>(grid.rows), std::vector<int>(grid.rows)} {
    number(0);
    if (grid.columns > 1) number(1);
  }

  int cell_of(std::size_t slot) {
    const auto rows = static_cast<std::size_t>(grid_.rows);
    const int column = static_cast<int>(slot / rows);
    while (column > first_column_ + 1) {
      std::swap(numbers_[0], numbers_[1]);
      ++first_column_;
      if (first_column_ + 1 < grid_.columns) number(first_column_ + 1);
    }
    if (column < first_column_) throw std::logic_error("fibrotic_sheet: the junctions went back a column");
    return numbers_[static_cast<std::size_t>(column - first_column_)][slot % rows];
  }

 private:
  // Numbers the next column's cells into its half (columns come in order).
  void number(int column) {
    std::vector<int>& numbers = numbers_[static_cast<std::size_t>(column - first_column_)];
    for (int r = 0; r < grid_.rows; ++r)
      numbers[static_cast<std::size_t>(r)] =
          SheetSlots::holds_cell(sheet_.kind(grid_.slot(column, r))) ? next_cell_++ : -1;
  }

  const SheetSlots& sheet_;
  const SheetGrid& grid_;
  std::array<std::vector<int>, 2> numbers_;  // columns first_column_ and first_column_ + 1
  int first_column_ = 0, next_cell_ = 0;
};

CellType cell_type_of(SlotKind kind) { return kind == SlotKind::myocyte ? CellType::myocyte : CellType::fibroblast; }

// The sheet's cells, centres and graph for a seed, handed over one at a
// time from its slots (a byte a slot), as build() numbers them and makes
// its graph: build_cells() is made from it too.
class SheetCellStream final : public CellStream {
 public:
  SheetCellStream(const SheetGrid& grid, const FibrosisSpec& fibrosis, FibrosisAs as, CollagenAs collagen,
                  std::uint64_t seed)
      : grid_(grid), sheet_(grid, fibrosis, as, collagen, seed) {}

  // The types, with build()'s particles and bonds counted and their bounds.
  Tissue cell_types() const override {
    std::size_t particles = 0, bonds = 0;
    std::array<double, 4> bounds = empty_bounds_um();
    sheet_.for_each_slot([&](int c, int r, std::size_t, SlotKind kind) {
      if (kind == SlotKind::empty) return;
      particles += kMyocyteParticles;
      if (SheetSlots::chained(kind)) bonds += kMyocyteParticles - 1;
      if (kind == SlotKind::collagen) return;  // (a tissue's bounds are its cells' particles')
      for (const Particle& p : sheet_.disks(c, r, kind, -1)) extend_bounds_um(bounds, p);
    });
    sheet_.for_each_junction([&](std::size_t a, std::size_t b, bool) {
      bonds += static_cast<std::size_t>(sheet_.touching_pairs(a, b, [](int, int) {}));
    });
    Tissue tissue;
    tissue.release_unbuilt_particles(particles, bonds, bounds);
    tissue.type.reserve(grid_.slots());
    sheet_.for_each_slot([&tissue](int, int, std::size_t, SlotKind kind) {
      if (SheetSlots::holds_cell(kind)) tissue.type.push_back(cell_type_of(kind));
    });
    tissue.type.shrink_to_fit();
    return tissue;
  }

  void for_each_cell(const std::function<void(int, CellType, double, double)>& visit) const override {
    int cell = 0;
    sheet_.for_each_slot([&](int c, int r, std::size_t, SlotKind kind) {
      if (!SheetSlots::holds_cell(kind)) return;
      const auto [x, y] = sheet_.centre_um(c, r, kind);
      visit(cell++, cell_type_of(kind), x, y);
    });
  }

  // The junctions' edges, which come in increasing order: a slot's cell is
  // numbered before the cells up its column and in the next column, and
  // its junctions go up, then to the next column's rows in order.
  void for_each_edge(const std::function<void(const CellCentre&, const CellCentre&)>& visit) const override {
    ColumnCellNumbers numbers(sheet_, grid_);
    sheet_.for_each_junction([&](std::size_t a, std::size_t b, bool septum) {
      const int cell_a = numbers.cell_of(a), cell_b = numbers.cell_of(b);
      if (!septum && cell_a >= 0 && cell_b >= 0) visit(sheet_.centre_of(a, cell_a), sheet_.centre_of(b, cell_b));
    });
  }

 private:
  SheetGrid grid_;
  SheetSlots sheet_;
};

// The particles of one slot: [first, first + count) of the tissue's
// particles, or of its collagen particles.
struct SlotParticles {
  int first = 0, count = 0;
  bool collagen = false;
};

class FibroticSheetBuilder final : public TissueBuilder {
 public:
  FibroticSheetBuilder(SheetGrid grid, FibrosisSpec fibrosis, FibrosisAs as, CollagenAs collagen)
      : grid_(grid), fibrosis_(fibrosis), as_(as), collagen_(collagen) {}

  Tissue build(std::uint64_t seed) const override {
    const SheetSlots sheet(grid_, fibrosis_, as_, collagen_, seed);
    Tissue tissue;
    std::vector<SlotParticles> slot(grid_.slots());
    tissue.type.reserve(grid_.slots());
    tissue.x_um.reserve(grid_.slots());
    tissue.y_um.reserve(grid_.slots());
    tissue.particles.reserve(kMyocyteParticles * grid_.slots());
    sheet.for_each_slot([&](int c, int r, std::size_t s, SlotKind kind) {
      if (kind == SlotKind::empty) return;
      const bool collagen = kind == SlotKind::collagen;
      const auto [x, y] = sheet.centre_um(c, r, kind);
      const int cell = collagen ? -1 : tissue.add_cell(cell_type_of(kind), x, y);
      slot[s] = {static_cast<int>(collagen ? tissue.collagen.size() : tissue.particles.size()), kMyocyteParticles,
                 collagen};
      for (const Particle& p : sheet.disks(c, r, kind, cell))
        if (collagen) tissue.add_collagen_particle(p.x_um, p.y_um, p.r_um);
        else tissue.add_particle(cell, p.x_um, p.y_um, p.r_um);
    });
    const int cell_particles = static_cast<int>(tissue.particles.size());
    tissue.bonds.reserve(7 * grid_.slots());  // a slot: 1 to the next up, 3 to each of 2 in the next column
    auto index = [&](const SlotParticles& s, int k) { return (s.collagen ? cell_particles : 0) + s.first + k; };
    // Bonds inside a slot of disks: each to the next (16.67 um apart).
    for (std::size_t s = 0; s < slot.size(); ++s)
      if (SheetSlots::chained(sheet.kind(s)))
        for (int k = 0; k + 1 < kMyocyteParticles; ++k) {
          if (slot[s].collagen) tissue.add_collagen_bond(index(slot[s], k), index(slot[s], k + 1));
          else tissue.add_bond(index(slot[s], k), index(slot[s], k + 1));
        }
    // Between neighbouring slots: every touching pair; through collagen where
    // either slot is collagen or a septum lies between them (no coupling).
    sheet.for_each_junction([&](std::size_t a, std::size_t b, bool septum) {
      const SlotParticles &sa = slot[a], &sb = slot[b];
      const bool through_collagen = septum || sa.collagen || sb.collagen;
      sheet.touching_pairs(a, b, [&](int i, int j) {
        if (through_collagen) tissue.add_collagen_bond(index(sa, i), index(sb, j));
        else tissue.add_bond(index(sa, i), index(sb, j));
      });
    });
    tissue.finalise();
    return tissue;
  }

  // build()'s cells and graph, counting its particles and bonds: the cell
  // graph's edges are the junctions that bond two cells' disks not through
  // collagen (each once, where build() adds one a bond).
  Tissue build_cells(std::uint64_t seed) const override {
    const SheetCellStream stream(grid_, fibrosis_, as_, collagen_, seed);
    Tissue tissue = stream.cell_types();
    tissue.x_um.reserve(tissue.cell_count());
    tissue.y_um.reserve(tissue.cell_count());
    stream.for_each_cell([&tissue](int, CellType, double x, double y) {
      tissue.x_um.push_back(x);
      tissue.y_um.push_back(y);
    });
    tissue.cell_edges.reserve(3 * grid_.slots());
    stream.for_each_edge(
        [&tissue](const CellCentre& a, const CellCentre& b) { tissue.cell_edges.emplace_back(a.cell, b.cell); });
    tissue.finalise();
    return tissue;
  }

  std::unique_ptr<CellStream> stream_cells(std::uint64_t seed) const override {
    return std::make_unique<SheetCellStream>(grid_, fibrosis_, as_, collagen_, seed);
  }

  // Counted slot by slot: a byte a slot, not the cells.
  std::size_t cell_count(std::uint64_t seed) const override {
    const SheetSlots sheet(grid_, fibrosis_, as_, collagen_, seed);
    std::size_t cells = 0;
    sheet.for_each_slot([&cells](int, int, std::size_t, SlotKind kind) {
      cells += SheetSlots::holds_cell(kind);
    });
    return cells;
  }

  void for_each_particle(std::uint64_t seed, const std::function<void(const Particle&)>& visit) const override {
    const SheetSlots sheet(grid_, fibrosis_, as_, collagen_, seed);
    int cell = 0;
    sheet.for_each_slot([&](int c, int r, std::size_t, SlotKind kind) {
      if (!SheetSlots::holds_cell(kind)) return;
      for (const Particle& p : sheet.disks(c, r, kind, cell)) visit(p);
      ++cell;
    });
  }

  bool builds_cells_alone() const override { return true; }

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
