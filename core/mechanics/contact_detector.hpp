// Contact detection for particles that are not bonded (REFERENCES.md 2.10):
// PFC detects every new contact and gives it the linear contact model; without
// this, bodies that were not touching at the start pass through one another
// (loose interstitial tissue folds and piles up).
//
// A Verlet list: the pairs of particles of different bodies, not joined by a
// bond, whose surfaces were within `skin` when the list was built, found on a
// uniform grid of cells no smaller than the largest cut-off (so a particle's
// candidates are in its 3 x 3 block of cells). The list stays complete until
// two particles together have moved or grown by `skin`: an unlisted pair had
// d0 > r_p0 + r_q0 + skin and touches only if |dx_p| + |dx_q| + (r_p - r_p0) +
// (r_q - r_q0) > skin, which needs_rebuild() bounds by 2 max_i (|dx_i| + dr_i).
//
// Deterministic: pairs (p < q) in ascending order, whatever the grid.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace fibrodem {

class ContactDetector {
 public:
  // body[i]: particle i's body (pebbles of one clump never touch each other);
  // bonded: the bonded pairs (their contact is the bond's); skin [m] > 0.
  ContactDetector(std::vector<int> body, const std::vector<std::pair<int, int>>& bonded, double skin_m);

  // True if some unlisted pair may have come into contact since the last build
  // (always before the first build).
  bool needs_rebuild(const double* x, const double* y, const double* r) const;
  // Lists the candidate pairs (p < q, ascending) at these positions and radii [m].
  void build(const double* x, const double* y, const double* r, std::vector<std::pair<int, int>>& pairs);

  std::size_t builds() const { return builds_; }
  double skin_m() const { return skin_; }

 private:
  bool bonded(int p, int q) const;

  std::vector<int> body_;
  // Bonded partners of each particle (CSR, ascending).
  std::vector<int> partner_begin_, partner_;
  double skin_;
  std::size_t builds_ = 0;
  // State at the last build.
  std::vector<double> x0_, y0_, r0_;
  // Grid scratch, kept between builds (no allocation once sized).
  std::vector<int> cell_of_, cell_start_, cell_fill_, order_;
};

}  // namespace fibrodem
