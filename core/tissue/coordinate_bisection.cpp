#include "tissue/coordinate_bisection.hpp"

#include <algorithm>
#include <numeric>

namespace fibrodem {

namespace {

struct Bisection {
  const std::vector<double>& x_um;
  const std::vector<double>& y_um;
  CellPitch pitch;
  std::size_t cells_per_part, parts_with_one_more;
  std::vector<int> part_of;

  std::size_t target_size(int part) const {
    return cells_per_part + (static_cast<std::size_t>(part) < parts_with_one_more ? 1 : 0);
  }

  // Whether the box of these cells is longer along x than along y, in cells.
  bool longer_along_x(std::vector<int>::iterator first, std::vector<int>::iterator last) const {
    const auto [x_low, x_high] = std::minmax_element(first, last, [&](int a, int b) { return x_um[a] < x_um[b]; });
    const auto [y_low, y_high] = std::minmax_element(first, last, [&](int a, int b) { return y_um[a] < y_um[b]; });
    return (x_um[*x_high] - x_um[*x_low]) / pitch.x_um >= (y_um[*y_high] - y_um[*y_low]) / pitch.y_um;
  }

  // Cells [first, last) into parts [part, part + parts).
  void split(std::vector<int>::iterator first, std::vector<int>::iterator last, int part, int parts) {
    if (parts == 1) {
      for (auto cell = first; cell != last; ++cell) part_of[static_cast<std::size_t>(*cell)] = part;
      return;
    }
    const int lower_parts = parts / 2;
    std::size_t lower_cells = 0;
    for (int p = part; p < part + lower_parts; ++p) lower_cells += target_size(p);
    const std::vector<double>& along = longer_along_x(first, last) ? x_um : y_um;
    const auto middle = first + static_cast<std::ptrdiff_t>(lower_cells);
    // A strict order (coordinate, then cell number): the same cells fall
    // below the median whatever nth_element's algorithm.
    std::nth_element(first, middle, last,
                     [&](int a, int b) { return along[a] < along[b] || (along[a] == along[b] && a < b); });
    split(first, middle, part, lower_parts);
    split(middle, last, part + lower_parts, parts - lower_parts);
  }
};

}  // namespace

std::vector<int> bisect_coordinates(const std::vector<double>& x_um, const std::vector<double>& y_um, CellPitch pitch,
                                    int parts) {
  const std::size_t n = x_um.size();
  Bisection bisection{x_um,
                      y_um,
                      pitch,
                      n / static_cast<std::size_t>(parts),
                      n % static_cast<std::size_t>(parts),
                      std::vector<int>(n, 0)};
  std::vector<int> cells(n);
  std::iota(cells.begin(), cells.end(), 0);
  bisection.split(cells.begin(), cells.end(), 0, parts);
  return std::move(bisection.part_of);
}

}  // namespace fibrodem
