#include "measure/cell_holes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace fibrodem {

namespace {
// The rim's sides, directed with the tissue on their left, and the sides
// leaving each cell (compressed rows).
struct RimSides {
  std::vector<int> from, to;
  std::vector<int> first_out, out;  // out[first_out[c] .. first_out[c + 1]) leave cell c
};

// Triangle sides whose reverse is not as often a side as they are: with a
// planar triangulation, those of one triangle only.
RimSides rim_sides(std::size_t cells, const std::vector<std::array<int, 3>>& triangles) {
  struct Side {
    int low, high, sign;  // sign +1: directed low -> high
  };
  std::vector<Side> sides;
  sides.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      sides.push_back(a < b ? Side{a, b, +1} : Side{b, a, -1});
    }
  std::sort(sides.begin(), sides.end(),
            [](const Side& p, const Side& q) { return std::pair(p.low, p.high) < std::pair(q.low, q.high); });
  RimSides rim;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    int net = 0;
    for (; j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high; ++j)
      net += sides[j].sign;
    for (int m = 0; m < std::abs(net); ++m) {
      rim.from.push_back(net > 0 ? sides[i].low : sides[i].high);
      rim.to.push_back(net > 0 ? sides[i].high : sides[i].low);
    }
    i = j;
  }
  rim.first_out.assign(cells + 1, 0);
  for (int a : rim.from) ++rim.first_out[a + 1];
  for (std::size_t c = 0; c < cells; ++c) rim.first_out[c + 1] += rim.first_out[c];
  rim.out.resize(rim.from.size());
  std::vector<int> next(rim.first_out.begin(), rim.first_out.end() - 1);
  for (std::size_t e = 0; e < rim.from.size(); ++e) rim.out[next[rim.from[e]]++] = static_cast<int>(e);
  return rim;
}

// The counter-clockwise turn in (0, 2 pi] from the way back (v -> u) to the
// way on (v -> w): the smallest sweeps the wedge without tissue on the right
// of the arriving side.
double counter_clockwise_turn(const Tissue& t, int u, int v, int w) {
  const double ax = t.x_um[u] - t.x_um[v], ay = t.y_um[u] - t.y_um[v];
  const double bx = t.x_um[w] - t.x_um[v], by = t.y_um[w] - t.y_um[v];
  double turn = std::atan2(ax * by - ay * bx, ax * bx + ay * by);
  if (turn <= 0) turn += 2 * std::numbers::pi;
  return turn;
}

// Every closed rim, walked from each side not yet walked. A walk that cannot
// close (only a non-planar graph gives one) is dropped.
std::vector<CellLoop> walk_rims(const Tissue& t, const RimSides& rim) {
  std::vector<CellLoop> loops;
  std::vector<char> walked(rim.from.size(), 0);
  for (std::size_t start = 0; start < rim.from.size(); ++start) {
    if (walked[start]) continue;
    CellLoop loop;
    int side = static_cast<int>(start);
    bool closed = false;
    while (true) {
      walked[side] = 1;
      loop.push_back(rim.from[side]);
      const int u = rim.from[side], v = rim.to[side];
      int best = -1;
      double best_turn = std::numeric_limits<double>::infinity();
      for (int k = rim.first_out[v]; k < rim.first_out[v + 1]; ++k) {
        const int next = rim.out[k];
        if (walked[next] && next != static_cast<int>(start)) continue;
        const double turn = counter_clockwise_turn(t, u, v, rim.to[next]);
        if (turn < best_turn) best_turn = turn, best = next;
      }
      if (best < 0) break;
      if (best == static_cast<int>(start)) {
        closed = true;
        break;
      }
      side = best;
    }
    if (closed) loops.push_back(std::move(loop));
  }
  return loops;
}

struct Polygon {
  double area_um2 = 0, cx_um = 0, cy_um = 0;  // signed area, centroid
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
};

Polygon polygon_of(const Tissue& t, const CellLoop& loop) {
  Polygon p;
  p.x_min = p.y_min = std::numeric_limits<double>::infinity();
  p.x_max = p.y_max = -std::numeric_limits<double>::infinity();
  double twice_area = 0, sx = 0, sy = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const int a = loop[i], b = loop[(i + 1) % loop.size()];
    const double cross = t.x_um[a] * t.y_um[b] - t.x_um[b] * t.y_um[a];
    twice_area += cross;
    sx += (t.x_um[a] + t.x_um[b]) * cross;
    sy += (t.y_um[a] + t.y_um[b]) * cross;
    p.x_min = std::min(p.x_min, t.x_um[a]), p.x_max = std::max(p.x_max, t.x_um[a]);
    p.y_min = std::min(p.y_min, t.y_um[a]), p.y_max = std::max(p.y_max, t.y_um[a]);
  }
  p.area_um2 = twice_area / 2;
  if (twice_area != 0) p.cx_um = sx / (3 * twice_area), p.cy_um = sy / (3 * twice_area);
  return p;
}

// Whether (x, y) lies inside the loop's polygon (crossings of a ray to +x).
bool inside(const Tissue& t, const CellLoop& loop, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const double xi = t.x_um[loop[i]], yi = t.y_um[loop[i]], xj = t.x_um[loop[j]], yj = t.y_um[loop[j]];
    if ((yi > y) != (yj > y) && x < xj + (y - yj) * (xi - xj) / (yi - yj)) in = !in;
  }
  return in;
}
}  // namespace

std::vector<CellHole> cell_holes(const Tissue& tissue, const std::vector<std::array<int, 3>>& triangles) {
  const RimSides rim = rim_sides(tissue.cell_count(), triangles);
  std::vector<CellHole> holes;
  std::vector<Polygon> hole_polygons;
  std::vector<CellLoop> outer;
  for (auto& loop : walk_rims(tissue, rim)) {
    const Polygon p = polygon_of(tissue, loop);
    if (p.area_um2 >= 0) {
      outer.push_back(std::move(loop));
      continue;
    }
    std::reverse(loop.begin(), loop.end());
    CellHole hole;
    hole.rim = std::move(loop);
    hole.x_mm = p.cx_um / 1000, hole.y_mm = p.cy_um / 1000;
    hole.area_mm2 = -p.area_um2 / 1e6;
    for (int c : hole.rim)
      hole.reach_mm = std::max(hole.reach_mm, std::hypot(tissue.x_um[c] - p.cx_um, tissue.y_um[c] - p.cy_um) / 1000);
    holes.push_back(std::move(hole));
    hole_polygons.push_back(p);
  }
  // Each outer rim belongs to the smallest hole around it, tested at the
  // midpoint of its first side: a rim side of one loop is never another's,
  // so that point is off every other rim.
  for (auto& island : outer) {
    const double x = (tissue.x_um[island[0]] + tissue.x_um[island[1 % island.size()]]) / 2;
    const double y = (tissue.y_um[island[0]] + tissue.y_um[island[1 % island.size()]]) / 2;
    int smallest = -1;
    for (std::size_t h = 0; h < holes.size(); ++h) {
      const Polygon& p = hole_polygons[h];
      if (x < p.x_min || x > p.x_max || y < p.y_min || y > p.y_max) continue;
      if (smallest >= 0 && holes[h].area_mm2 >= holes[smallest].area_mm2) continue;
      if (inside(tissue, holes[h].rim, x, y)) smallest = static_cast<int>(h);
    }
    if (smallest >= 0) holes[smallest].islands.push_back(std::move(island));
  }
  return holes;
}

}  // namespace fibrodem
