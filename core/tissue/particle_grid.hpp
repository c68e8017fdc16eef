// A uniform grid of square bins over a rectangle for overlap and touch queries
// between disks of mixed sizes. Each disk is registered in every bin that its
// bounding square (plus a margin) covers, so a query only visits the bins
// covered by the query disk: any registered disk that could touch it is seen
// (perhaps more than once; callers that count pairs de-duplicate).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace fibrodem {

class ParticleGrid {
 public:
  // The rectangle [x0, x1] x [y0, y1], bins of side `bin_um`; `margin_um` widens
  // every registration (the largest gap a query should still find).
  ParticleGrid(double x0, double x1, double y0, double y1, double bin_um, double margin_um)
      : x0_(x0), y0_(y0), bin_(bin_um), margin_(margin_um),
        nx_(std::max(1, static_cast<int>(std::ceil((x1 - x0) / bin_um)))),
        ny_(std::max(1, static_cast<int>(std::ceil((y1 - y0) / bin_um)))),
        bins_(static_cast<std::size_t>(nx_) * ny_) {}

  // Registers item `id` as a disk at (x, y) of radius r; may be called again
  // for the same id after it grew (its old bins stay registered: a superset).
  void insert(int id, double x, double y, double r) {
    for_bins(x, y, r + margin_, [&](std::vector<int>& bin) { bin.push_back(id); });
  }

  // Calls f(id) for every item registered in a bin that the disk (x, y, r) covers.
  // Returns early (false) if f returns false.
  template <class F>
  bool visit(double x, double y, double r, F&& f) const {
    const int ia = clamp_x(x - r), ib = clamp_x(x + r);
    const int ja = clamp_y(y - r), jb = clamp_y(y + r);
    for (int j = ja; j <= jb; ++j)
      for (int i = ia; i <= ib; ++i)
        for (int id : bins_[static_cast<std::size_t>(j) * nx_ + i])
          if (!f(id)) return false;
    return true;
  }

 private:
  int clamp_x(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / bin_)), 0, nx_ - 1);
  }
  int clamp_y(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / bin_)), 0, ny_ - 1);
  }
  template <class F>
  void for_bins(double x, double y, double r, F&& f) {
    const int ia = clamp_x(x - r), ib = clamp_x(x + r);
    const int ja = clamp_y(y - r), jb = clamp_y(y + r);
    for (int j = ja; j <= jb; ++j)
      for (int i = ia; i <= ib; ++i) f(bins_[static_cast<std::size_t>(j) * nx_ + i]);
  }

  double x0_, y0_, bin_, margin_;
  int nx_, ny_;
  std::vector<std::vector<int>> bins_;
};

// Deterministic random numbers for the builders: std::mt19937_64 (its output is
// fixed by the standard) with our own conversions, since the standard
// distributions' outputs differ between library implementations.
class BuilderRandom {
 public:
  explicit BuilderRandom(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  // True with probability p.
  bool chance(double p) { return uniform() < p; }
  // Uniform integer in [0, n), n > 0 (rejection sampling, no modulo bias).
  std::uint64_t below(std::uint64_t n) {
    const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
    std::uint64_t v;
    do v = engine_(); while (v >= limit);
    return v % n;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace fibrodem
