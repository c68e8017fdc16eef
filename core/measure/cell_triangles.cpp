#include "measure/cell_triangles.hpp"

#include <algorithm>
#include <cmath>

namespace fibrodem {

namespace {
double signed_area_um2(const Tissue& t, int a, int b, int c) {
  return 0.5 * ((t.x_um[b] - t.x_um[a]) * (t.y_um[c] - t.y_um[a]) -
                (t.x_um[c] - t.x_um[a]) * (t.y_um[b] - t.y_um[a]));
}

// Appends (a, b, c) counter-clockwise, unless its centres are collinear.
void add_triangle(const Tissue& t, int a, int b, int c, std::vector<std::array<int, 3>>& out) {
  const double area = signed_area_um2(t, a, b, c);
  if (std::abs(area) < 1e-9) return;
  if (area > 0) out.push_back({a, b, c});
  else out.push_back({a, c, b});
}

double distance_um(const Tissue& t, int a, int b) { return std::hypot(t.x_um[a] - t.x_um[b], t.y_um[a] - t.y_um[b]); }
}  // namespace

std::vector<std::array<int, 3>> cell_triangles(const Tissue& tissue) {
  const std::size_t n = tissue.cell_count();
  std::vector<std::vector<int>> neighbours(n);
  for (const auto& [a, b] : tissue.cell_edges) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  for (auto& list : neighbours) std::sort(list.begin(), list.end());
  auto adjacent = [&](int a, int b) { return std::binary_search(neighbours[a].begin(), neighbours[a].end(), b); };

  std::vector<std::array<int, 3>> triangles;
  // 3-cliques a < b < c, each found once from its smallest cell.
  for (int a = 0; a < static_cast<int>(n); ++a)
    for (int b : neighbours[a]) {
      if (b <= a) continue;
      for (int c : neighbours[b])
        if (c > b && adjacent(a, c)) add_triangle(tissue, a, b, c, triangles);
    }
  // Chordless 4-cycles a-b-c-d with a the smallest and b < d (each once).
  for (int a = 0; a < static_cast<int>(n); ++a)
    for (int b : neighbours[a]) {
      if (b <= a) continue;
      for (int c : neighbours[b]) {
        if (c <= a || c == b || adjacent(a, c)) continue;
        for (int d : neighbours[c]) {
          if (d <= b || d == a || !adjacent(d, a) || adjacent(b, d)) continue;
          if (distance_um(tissue, a, c) <= distance_um(tissue, b, d)) {
            add_triangle(tissue, a, b, c, triangles);
            add_triangle(tissue, a, c, d, triangles);
          } else {
            add_triangle(tissue, a, b, d, triangles);
            add_triangle(tissue, b, c, d, triangles);
          }
        }
      }
    }
  return triangles;
}

}  // namespace fibrodem
