// Per-cell strain of a deforming tissue, from the displacements of each
// cell's neighbours on the cell graph (Tissue::cell_edges): the local
// deformation gradient by least squares, as molecular dynamics measures the
// strain at an atom from its neighbours (Falk & Langer 1998, Phys Rev E
// 57:7192, eq. 2.11-2.12; Shimizu, Ogata & Li 2007, Mater Trans 48:2923,
// whose "atomic strain" OVITO computes; Zimmerman, Bammann & Gao 2009, Int J
// Solids Struct 46:238, on its continuum meaning).
//
// For cell i with neighbours j, reference separations d0_j = X_j - X_i (the
// cells' centroids as built) and present ones d_j = x_j - x_i, the
// displacement gradient H = F - I minimising sum_j |d_j - F d0_j|^2 is
//   H = (sum_j (d_j - d0_j) d0_j^T) (sum_j d0_j d0_j^T)^-1
// and the Green-Lagrange strain
//   E = (F^T F - I) / 2 = (H + H^T + H^T H) / 2,
// formed from H rather than from F^T F - I so that strains of 1e-4 keep
// their digits. A rigid motion gives E = 0 (to round-off), an affine
// deformation of the neighbourhood its exact E (the fit is exact).
//
// Reported per cell: E_xx, E_yy, E_xy (tensor components), the fibre
// stretch lambda_f = |F e_y| = sqrt(1 + 2 E_yy) (the fibres run along y in
// every builder; 1 at rest, < 1 shortened), and the largest shear strain
// over all orientations, the radius of Mohr's circle,
// sqrt(((E_xx - E_yy) / 2)^2 + E_xy^2).
//
// A cell whose neighbours do not span the plane (none, one, or all on one
// line through it: a lone cell, a cell of a one-cell-wide strand) has no
// unique F: its fields are NaN. "On one line": the smaller eigenvalue of
// sum_j d0_j d0_j^T below kCollinear times the larger.
#pragma once

#include <cstddef>
#include <vector>

#include "tissue/tissue.hpp"

namespace fibrodem {

struct CellStrainField {
  std::vector<double> E_xx, E_yy, E_xy, fibre_stretch, max_shear;  // per cell; NaN: unresolved
};

class CellStrain {
 public:
  static constexpr double kCollinear = 1e-6;

  // The tissue's graph and its cells' reference positions: the centroid of
  // each cell's particles as built (tissue.particles; a cell without
  // particles: its x_um, y_um).
  explicit CellStrain(const Tissue& tissue);

  // The field with the particles where they are now (tissue order, as
  // MechanicsSolver::particles()). Cells are taken in blocks on the OpenMP
  // threads, each cell on its own: the same bits on any thread count. No
  // allocation after the first call.
  const CellStrainField& compute(const std::vector<Particle>& particles_now);
  // The same from the cells' positions now [um].
  const CellStrainField& compute_from_centroids(const std::vector<double>& x_um, const std::vector<double>& y_um);

  const CellStrainField& field() const { return field_; }
  std::size_t cell_count() const { return x0_.size(); }
  // Cells whose neighbours do not span the plane (NaN fields).
  std::size_t unresolved_cells() const { return unresolved_; }

 private:
  void centroids(const std::vector<Particle>& particles, std::vector<double>& x, std::vector<double>& y) const;
  void strain_of_cell(std::size_t i);

  std::vector<double> x0_, y0_;                                // reference centroids [um]
  std::vector<int> neighbour_start_, neighbour_;               // the cell graph (CSR, ascending)
  std::vector<int> particle_start_, particle_;                 // each cell's particles (CSR, ascending)
  std::vector<double> Y_inv_xx_, Y_inv_xy_, Y_inv_yy_;         // (sum d0 d0^T)^-1; NaN: unresolved
  std::size_t unresolved_ = 0;
  std::vector<double> x_, y_;                                  // present centroids [um]
  CellStrainField field_;
};

}  // namespace fibrodem
