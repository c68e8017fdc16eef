// Contact detection for particles that are not bonded
// (docs/reference/references.md#dem-contact-detection):
// PFC detects every new contact and gives it the linear contact model; without
// this, bodies that were not touching at the start pass through one another
// (loose interstitial tissue folds and piles up).
//
// A Verlet list: the pairs of particles of different bodies, not joined by a
// bond, whose surfaces were within `skin` when the list was built, found on a
// uniform grid of cells no smaller than the largest cut-off (so a particle's
// candidates are in its 3 x 3 block of cells).
//
// When to rebuild: the whole tissue shortens by ~10 % in a twitch, so its far
// ends move hundreds of um while neighbours barely move relative to each
// other. Positions are written x_i = c + A (x0_i - c0) + u_i, A the best-fit
// affine map since the build (any A would do; the fit keeps u small). For an
// unlisted pair, |x0_q - x0_p| >= R + skin with R = r0_p + r0_q, so
// |x_q - x_p| >= s_min(A) (R + skin) - 2 u_max, and contact needs
// |x_q - x_p| < R + 2 dr_max (radius growth): the list is complete while
// s_min (R + skin) - R >= 2 (u_max + dr_max) for the worst R (2 r_max if A
// compresses, else 0). Without a fit (particles on a line) A = identity.
// Deterministic: pairs (p < q) in ascending order, whatever the grid and the
// number of threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "io/checkpoint_file.hpp"

namespace fibrodem {

class ContactDetector {
 public:
  // body[i]: particle i's body (pebbles of one clump never touch each other);
  // bonded: the bonded pairs (their contact is the bond's); skin [m] > 0.
  ContactDetector(std::vector<int> body, const std::vector<std::pair<int, int>>& bonded, double skin_m);

  // The affine fit's sums over the particles (in a caller's fixed order, for
  // the same bits on any number of threads): positions x, y from any origin
  // and their products with the built positions, (x, y)(x0 - c0, y0 - c0)^T.
  using FitSums = std::array<double, 6>;
  // Adds the terms of particles ids[0..count) at x[i] - ox, y[i] - oy.
  void add_fit_terms(const int* ids, int count, const double* x, const double* y, double ox, double oy,
                     FitSums& acc) const {
    if (x0_.empty()) return;  // not built yet
    const double *const x0 = x0_.data(), *const y0 = y0_.data();
    FitSums sum = acc;  // (local: the loop's stores cannot alias x0 and y0)
    for (int j = 0; j < count; ++j) {
      const int i = ids[j];
      const double px = x[i] - ox, py = y[i] - oy, dx0 = x0[i] - cx0_, dy0 = y0[i] - cy0_;
      sum[0] += px;
      sum[1] += py;
      sum[2] += px * dx0;
      sum[3] += px * dy0;
      sum[4] += py * dx0;
      sum[5] += py * dy0;
    }
    acc = sum;
  }
  // True if some unlisted pair may have come into contact since the last build
  // (always before the first build), given the sums over these positions
  // taken from (origin_x, origin_y).
  bool needs_rebuild(const FitSums& sums, double origin_x, double origin_y, const double* x, const double* y,
                     const double* r) const;
  // needs_rebuild() in its three parts, for a DEM split over ranks
  // (mechanics/dem_split.hpp), where each rank holds the present places of
  // its own particles only: the best-fit affine map from the sums over
  // every particle; the departures from it of particles [begin, end),
  // maxima that combine in any order (max of each field); and the decision.
  struct AffineFit {
    double cx = 0, cy = 0, a00 = 1, a01 = 0, a10 = 0, a11 = 1;
  };
  struct Departure {
    double u2 = 0, dr = 0;  // largest squared departure, radius growth [m^2, m]
    double not_finite = 0;  // 1 if some position or radius is not finite
  };
  AffineFit affine_fit(const FitSums& sums, double origin_x, double origin_y) const;
  Departure departure(const AffineFit& fit, const double* x, const double* y, const double* r, std::size_t begin,
                      std::size_t end) const;
  bool beyond_skin(const AffineFit& fit, const Departure& d) const;
  bool built() const { return builds_ > 0; }
  // The same, summing the positions itself.
  bool needs_rebuild(const double* x, const double* y, const double* r) const;
  // Lists the candidate pairs (p < q, ascending) at these positions and radii
  // [m]; throws std::runtime_error naming a particle whose position is not finite.
  void build(const double* x, const double* y, const double* r, std::vector<std::pair<int, int>>& pairs);

  std::size_t builds() const { return builds_; }
  // The state at the last build, for a checkpoint (prefix "dem.detector.").
  void save(CheckpointFields& fields) const;
  void load(const CheckpointFields& fields);
  double skin_m() const { return skin_; }

 private:
  bool bonded(int p, int q) const;
  void add_pairs_of(int p, const double* x, const double* y, const double* r, long nx, long ny,
                    std::vector<std::pair<int, int>>& pairs) const;
  void remember_moments();
  void remember_offset_sums();

  std::vector<int> body_;
  // Bonded partners of each particle (CSR, ascending).
  std::vector<int> partner_begin_, partner_;
  double skin_;
  std::size_t builds_ = 0;
  // State at the last build: positions, radii, their centroid, the inverse of
  // their second moment (for the affine fit; affine_ false if singular).
  std::vector<double> x0_, y0_, r0_;
  double cx0_ = 0, cy0_ = 0, rmax0_ = 0;
  double ex0_ = 0, ey0_ = 0;  // sum of (x0 - c0, y0 - c0): zero but for rounding
  double s0inv_[2][2] = {{0, 0}, {0, 0}};
  bool affine_ = false;
  // Grid scratch, kept between builds (no allocation once sized).
  std::vector<int> cell_of_, cell_start_, cell_fill_, order_;
  static constexpr std::size_t kChunks = 64;  // runs of particles searched on the threads
  std::vector<std::vector<std::pair<int, int>>> chunk_pairs_;  // each run's pairs
};

}  // namespace fibrodem
