// The geometry and connectivity of a tissue: cells, the particles that make
// them up (for mechanics), bonds between particles, and the cell graph that
// carries gap-junction currents (two cells are neighbours if a bond joins them).
// Collagen particles belong to no cell: they are the mechanics' only, with
// bonds of their own that couple no cells.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "model/cell_type.hpp"

namespace fibrodem {

// What the outputs keep of released particles (io/tissue_imprint.hpp).
struct TissueImprint;
// A tissue's cells handed over one at a time (tissue/cell_stream.hpp).
class CellStream;

// A cell and its centre.
struct CellCentre {
  int cell = -1;
  double x_um = 0, y_um = 0;
};

struct Particle {
  double x_um = 0, y_um = 0, r_um = 0;
  int cell = -1;
};

struct Bond {
  int p = -1, q = -1;  // particle indices
};

struct Tissue {
  std::vector<CellType> type;                   // per cell (empty if held in part: hold_cells_of)
  std::vector<double> x_um, y_um;               // cell centroids (likewise)
  std::vector<Particle> particles;
  std::vector<Bond> bonds;
  std::vector<std::pair<int, int>> cell_edges;  // unique, i < j, sorted
  // Collagen (fibrotic_sheet's `collagen: particles`): particles of no cell
  // (cell -1), for the mechanics only (in no picture, no cell graph), and the
  // bonds through collagen, which couple no cells and take the collagen's
  // stiffness: bonds to a collagen particle and, across an interstitial
  // septum, between the particles of two cells. Their particle indices count
  // `particles` first, then `collagen` (index particles.size() + k is collagen[k]).
  std::vector<Particle> collagen;
  std::vector<Bond> collagen_bonds;

  std::size_t cell_count() const { return cells_partial_ ? partial_cell_count_ : type.size(); }
  std::size_t count(CellType t) const;
  // Bounding box of the particles (cell centroids if there are none).
  std::array<double, 4> bounds_um() const;  // x_min, x_max, y_min, y_max

  int add_cell(CellType t, double x_um, double y_um);
  int add_particle(int cell, double x_um, double y_um, double r_um);
  // Bonds particles p and q and records the cell edge if they belong to two cells.
  void add_bond(int p, int q);
  // A collagen particle (returns its index in `collagen`) and a bond through
  // collagen (indices counted over particles, then collagen: see `collagen_bonds`).
  int add_collagen_particle(double x_um, double y_um, double r_um);
  void add_collagen_bond(int p, int q) { collagen_bonds.push_back({p, q}); }
  // Sorts and de-duplicates the cell edges; call once the builder is done.
  void finalise();
  // Frees the particles and bonds (collagen's too), keeping the cells, their
  // graph and the bounds the particles gave (bounds_um() is unchanged): for
  // a process that neither steps the DEM nor draws the tissue, such as a
  // rank other than 0 of a split run (docs/guide/parallel.md). With an
  // imprint, what the pictures and VTK files need of them is kept in it
  // (rank 0 of a split run without mechanics).
  void release_particles(std::shared_ptr<const TissueImprint> imprint = nullptr);
  // A tissue whose builder made its cells without their particles and
  // bonds (TissueBuilder::build_cells): released as if it had held
  // `particle_count` particles and `bond_count` bonds (collagen's included)
  // within `bounds_um`.
  void release_unbuilt_particles(std::size_t particle_count, std::size_t bond_count, const std::array<double, 4>& bounds_um);
  bool particles_released() const { return particles_released_; }
  // Frees the cells' centres (x_um, y_um), keeping their types, or a
  // tissue holding part of its cells every cell held, keeping their counts:
  // for a rank other than 0 of a split run once it has started, which
  // reads them no more (docs/guide/parallel.md). The particles must have
  // been released.
  void release_centres();
  // Whether x_um and y_um hold every cell's centre (a tissue holding part
  // of its cells holds neither), and whether the centres are neither held
  // nor at hand (released: for_each_centre refused).
  bool centres_whole() const { return !cells_partial_ && x_um.size() == type.size(); }
  bool centres_released() const { return !centres_whole() && !every_cell_; }

  // Holds some cells alone, `held` by increasing cell number (a rank of a
  // split run: its own cells and ghosts), with their types and centres;
  // every cell's type and centre come from `every_cell` when asked for all
  // (a builder's stream, which need not hold them), until the centres are
  // released. The types are taken from `type`, which must hold every
  // cell's; type, x_um and y_um are then empty (docs/guide/parallel.md).
  void hold_cells_of(std::vector<CellCentre> held, std::shared_ptr<const CellStream> every_cell);
  bool cells_partial() const { return cells_partial_; }
  // The cells a tissue holding part of them holds (empty otherwise).
  const std::vector<CellCentre>& held_cells() const { return held_cells_; }
  // A cell's type and centre, held whole or in part (std::logic_error if
  // not held, or its centre released).
  CellType type_of(int cell) const;
  CellCentre centre_of(int cell) const;
  // The types of some cells, held or not: a tissue holding part of its
  // cells reads those it does not hold from its stream, in one pass.
  std::vector<CellType> types_of(const std::vector<int>& cells) const;
  // Every cell by increasing cell number, visit(cell, type, x_um, y_um), and
  // every cell's centre alone, visit(cell, x_um, y_um): from type, x_um and
  // y_um, or from the stream of a tissue holding part of its cells
  // (std::logic_error if the centres were released). for_each_type needs
  // no centres where the types are whole.
  void for_each_cell(const std::function<void(int, CellType, double, double)>& visit) const;
  void for_each_centre(const std::function<void(int, double, double)>& visit) const;
  void for_each_type(const std::function<void(int, CellType)>& visit) const;
  // Keeps of the cell graph the edges `kept` (in cell_edges' order),
  // counting the whole graph's `edges` as built: for a rank of a split run,
  // which never holds the whole graph (docs/guide/parallel.md).
  void keep_part_of_graph(std::vector<std::pair<int, int>> kept, std::size_t edges);
  bool graph_partial() const { return graph_partial_; }
  // The cell graph's edges as built, all held or not.
  std::size_t built_cell_edges() const { return graph_partial_ ? built_cell_edges_ : cell_edges.size(); }
  // The imprint the particles were released with (null: none).
  const TissueImprint* imprint() const { return imprint_.get(); }
  // Particles and bonds as built (collagen's included), released or not.
  std::size_t built_particles() const {
    return particles_released_ ? released_particles_ : particles.size() + collagen.size();
  }
  std::size_t built_bonds() const {
    return particles_released_ ? released_bonds_ : bonds.size() + collagen_bonds.size();
  }

 private:
  bool particles_released_ = false;
  std::array<double, 4> released_bounds_um_{};
  std::size_t released_particles_ = 0, released_bonds_ = 0;
  bool graph_partial_ = false;
  std::size_t built_cell_edges_ = 0;
  std::shared_ptr<const TissueImprint> imprint_;
  // A tissue holding part of its cells: those held, their types, every
  // cell's count and each type's, and the stream of every cell.
  bool cells_partial_ = false;
  std::vector<CellCentre> held_cells_;
  std::vector<CellType> held_types_;
  std::size_t partial_cell_count_ = 0, partial_myocytes_ = 0;
  std::shared_ptr<const CellStream> every_cell_;
  // A held cell's place in held_cells_: or held_cells_.size() if not held
  // (find_held), or std::logic_error (held_index).
  std::size_t find_held(int cell) const;
  std::size_t held_index(int cell) const;
};

// A bounding box (x_min, x_max, y_min, y_max) that holds nothing yet, and
// one widened to hold particle p.
std::array<double, 4> empty_bounds_um();
void extend_bounds_um(std::array<double, 4>& bounds, const Particle& p);

// Geometry of the paper's cells (seed paper, section 2.2): a myocyte is 7
// particles of radius 12.5 um at spacing 16.67 um along its axis (125 x 25 um);
// a fibroblast particle has radius 12.5 um.
inline constexpr int kMyocyteParticles = 7;
inline constexpr double kParticleRadius_um = 12.5;
inline constexpr double kMyocyteLength_um = 125.0;
inline constexpr double kParticleSpacing_um =
    (kMyocyteLength_um - 2 * kParticleRadius_um) / (kMyocyteParticles - 1);

// Distance from a myocyte's centre to the centre of its end particle (50 um).
inline constexpr double kMyocyteEndOffset_um = (kMyocyteParticles - 1) * kParticleSpacing_um / 2;

// Adds a myocyte centred at (x, y) whose axis makes `angle_rad` with the y axis
// (positive = counter-clockwise: the top end moves to -x); its particles are
// consecutive, from the bottom end to the top end. Returns the cell.
int add_myocyte(Tissue& tissue, double x_um, double y_um, double angle_rad);
// Adds a vertical myocyte (axis along y) whose lowest point is at y0; returns the cell.
int add_vertical_myocyte(Tissue& tissue, double x_um, double y0_um);
// Adds a one-particle fibroblast centred at (x, y); returns the cell.
int add_round_fibroblast(Tissue& tissue, double x_um, double y_um);

// Whether the junction between cells i and j joins them end to end, along
// the fibres (y in every builder), rather than side to side: their centres
// lie within half a myocyte's width (12.5 um) of each other across the
// fibres. On the brick sheets (fibrotic_sheet, in_series) that is a cell and
// the one above it in its column; a side neighbour is a column (23.57 um)
// away. In interstitial tissue a cell's neighbours in its column are offset
// by at most 2 x max_offset_um (4 um by default).
bool end_to_end(const Tissue& tissue, int i, int j);

// Connected components of the cell graph (cells joined by cell_edges).
struct CellComponents {
  std::vector<int> component;  // per cell; components numbered by their lowest cell
  std::vector<int> size;       // cells per component
  std::size_t count() const { return size.size(); }
  // Index of the largest component (the lowest-numbered one on ties); -1 if no cells.
  int largest() const;
};
CellComponents cell_graph_components(const Tissue& tissue);

}  // namespace fibrodem
