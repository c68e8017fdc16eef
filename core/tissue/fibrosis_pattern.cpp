#include "tissue/fibrosis_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace fibrodem {
namespace {

std::size_t target_count(const SheetGrid& grid, double density) {
  return static_cast<std::size_t>(std::llround(density * static_cast<double>(grid.slots())));
}

std::vector<char> diffuse(const SheetGrid& grid, double density, BuilderRandom& rng) {
  std::vector<char> out(grid.slots(), 0);
  for (auto& s : out) s = rng.chance(density) ? 1 : 0;
  return out;
}

// Normalised Gaussian weights exp(-k^2 / (2 sigma^2)), k in [-3 sigma, 3 sigma].
std::vector<double> gaussian_kernel(double sigma) {
  const int half = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> w(2 * half + 1);
  for (int k = -half; k <= half; ++k) w[k + half] = sigma > 0 ? std::exp(-0.5 * k * k / (sigma * sigma)) : 1.0;
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (auto& v : w) v /= sum;
  return w;
}

// White noise filtered by a Gaussian of standard deviation sigma has the
// autocorrelation exp(-d^2 / (4 sigma^2)); sigma = correlation_length / 2 puts
// its 1/e point at the correlation length. The noise is drawn on the grid
// widened by the kernel's reach on every side, so that the field is stationary
// up to the edges (no wrap-around, no edge effect). Odd columns' half-cell
// shift is ignored in the filter (it moves a sample by a quarter of pitch_y
// on average, against correlation lengths of several pitches).
std::vector<double> smoothed_noise(const SheetGrid& grid, double correlation_length_um, BuilderRandom& rng) {
  const double sigma_um = correlation_length_um / 2;
  const std::vector<double> wx = gaussian_kernel(sigma_um / grid.pitch_x_um);
  const std::vector<double> wy = gaussian_kernel(sigma_um / grid.pitch_y_um);
  const int hx = static_cast<int>(wx.size() / 2), hy = static_cast<int>(wy.size() / 2);
  const int cols = grid.columns + 2 * hx, rows = grid.rows + 2 * hy;
  std::vector<double> noise(static_cast<std::size_t>(cols) * rows);
  for (auto& v : noise) v = rng.uniform() - 0.5;
  // Along y (rows of one column are contiguous), keeping the grid's rows only.
  std::vector<double> along_y(static_cast<std::size_t>(cols) * grid.rows, 0.0);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < grid.rows; ++r) {
      const double* in = &noise[static_cast<std::size_t>(c) * rows + r];  // row r - hy of the wide grid's window
      double s = 0;
      for (std::size_t k = 0; k < wy.size(); ++k) s += wy[k] * in[k];
      along_y[static_cast<std::size_t>(c) * grid.rows + r] = s;
    }
  // Along x, keeping the grid's columns only.
  std::vector<double> field(grid.slots(), 0.0);
  for (int c = 0; c < grid.columns; ++c)
    for (std::size_t k = 0; k < wx.size(); ++k) {
      const double w = wx[k];
      const double* in = &along_y[(c + k) * static_cast<std::size_t>(grid.rows)];
      double* out = &field[grid.slot(c, 0)];
      for (int r = 0; r < grid.rows; ++r) out[r] += w * in[r];
    }
  return field;
}

// The round(density * slots) slots of highest field value (ties by slot index,
// so the choice is a strict order and deterministic).
std::vector<char> patchy(const SheetGrid& grid, const FibrosisSpec& spec, BuilderRandom& rng) {
  const std::vector<double> field = smoothed_noise(grid, spec.correlation_length_um, rng);
  const std::size_t n = grid.slots(), k = target_count(grid, spec.density);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto higher = [&field](std::size_t a, std::size_t b) { return field[a] > field[b] || (field[a] == field[b] && a < b); };
  if (k > 0 && k < n) std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(), higher);
  std::vector<char> out(n, 0);
  for (std::size_t i = 0; i < k; ++i) out[order[i]] = 1;
  return out;
}

// Lines of consecutive slots along a column, started at uniformly drawn slots
// (a line that runs past the sheet's end is cut there), until at least
// round(density * slots) slots are fibrotic; overlapping lines merge.
std::vector<char> interstitial(const SheetGrid& grid, const FibrosisSpec& spec, BuilderRandom& rng) {
  const std::size_t target = target_count(grid, spec.density);
  const int length = std::max(1, static_cast<int>(std::lround(spec.line_length_um / grid.pitch_y_um)));
  std::vector<char> out(grid.slots(), 0);
  std::size_t marked = 0;
  while (marked < target) {
    const std::size_t start = rng.below(grid.slots());
    const int c = static_cast<int>(start / grid.rows), r0 = static_cast<int>(start % grid.rows);
    for (int r = r0; r < std::min(grid.rows, r0 + length) && marked < target; ++r) {
      char& s = out[grid.slot(c, r)];
      if (!s) ++marked;
      s = 1;
    }
  }
  return out;
}

// The slots whose centres lie in a rectangle of area density * sheet area,
// length/width = aspect, centred at the given fractions of the sheet.
std::vector<char> compact(const SheetGrid& grid, const FibrosisSpec& spec) {
  const double area = spec.density * grid.width_um() * grid.length_um();
  const double w = std::sqrt(area / spec.aspect), h = w * spec.aspect;
  const double cx = spec.centre_x_frac * grid.width_um(), cy = spec.centre_y_frac * grid.length_um();
  std::vector<char> out(grid.slots(), 0);
  for (int c = 0; c < grid.columns; ++c) {
    if (std::abs(grid.x_um(c) - cx) >= w / 2) continue;
    for (int r = 0; r < grid.rows; ++r)
      if (std::abs(grid.y_um(c, r) - cy) < h / 2) out[grid.slot(c, r)] = 1;
  }
  return out;
}

}  // namespace

std::vector<char> fibrotic_slots(const SheetGrid& grid, const FibrosisSpec& spec, BuilderRandom& rng) {
  if (spec.density <= 0) return std::vector<char>(grid.slots(), 0);
  switch (spec.pattern) {
    case FibrosisPattern::diffuse: return diffuse(grid, spec.density, rng);
    case FibrosisPattern::patchy: return patchy(grid, spec, rng);
    case FibrosisPattern::interstitial: return interstitial(grid, spec, rng);
    case FibrosisPattern::compact: return compact(grid, spec);
  }
  return {};
}

FibrosisPattern fibrosis_pattern_from_name(const std::string& name) {
  for (std::size_t i = 0; i < kFibrosisPatternNames.size(); ++i)
    if (kFibrosisPatternNames[i] == name) return static_cast<FibrosisPattern>(i);
  throw std::invalid_argument("unknown fibrosis pattern " + name);
}

}  // namespace fibrodem
