#include "tissue/builders/column_tissue.hpp"

#include <algorithm>
#include <numeric>

#include "tissue/particle_grid.hpp"

namespace fibrodem {
namespace {

constexpr double kRadius = kParticleRadius_um;
constexpr double kEnd = kMyocyteEndOffset_um;
constexpr double kBin_um = 8.0;
constexpr double kMargin_um = 0.05;     // >= half the largest touch tolerance
constexpr int kRotationAttempts = 30;   // draws of (angle, offset) before a straight myocyte
constexpr double kScanStep_um = 0.25;   // upward scan for a free place after an obstacle
constexpr double kPushStep_um = 0.25;   // sideways push of a rotated myocyte off its neighbours
constexpr double kMaxPush_um = kRadius;

struct Point {
  double x, y;
};

// All particles of the tissue under construction: the column cells' particles
// (in the Tissue, in order) followed by the interstitial fill particles.
class Workspace {
 public:
  Workspace(const ColumnTissueSpec& spec)
      : grid(-kRadius, spec.width_um + kRadius, -kRadius, spec.height_um + kRadius, kBin_um,
             kMargin_um) {}

  Tissue tissue;
  std::vector<Particle> fill;  // cell -1 until grouped
  ParticleGrid grid;

  std::size_t column_particles() const { return tissue.particles.size(); }
  std::size_t size() const { return tissue.particles.size() + fill.size(); }
  const Particle& at(int id) const {
    const auto n = static_cast<int>(tissue.particles.size());
    return id < n ? tissue.particles[id] : fill[id - n];
  }
  Particle& at(int id) {
    const auto n = static_cast<int>(tissue.particles.size());
    return id < n ? tissue.particles[id] : fill[id - n];
  }

  // True if a disk at (x, y, r) overlaps any particle by more than `allowed`.
  bool overlaps(double x, double y, double r, double allowed) const {
    return !grid.visit(x, y, r, [&](int id) {
      const Particle& q = at(id);
      const double reach = r + q.r_um - allowed;
      const double dx = q.x_um - x, dy = q.y_um - y;
      return dx * dx + dy * dy >= reach * reach;
    });
  }
  // Largest radius for a disk at (x, y) that overlaps nothing, searching up to `r_max`.
  double free_radius(int self, double x, double y, double r_max) const {
    double limit = r_max;
    grid.visit(x, y, r_max, [&](int id) {
      if (id == self) return true;
      const Particle& q = at(id);
      const double d = std::hypot(q.x_um - x, q.y_um - y) - q.r_um;
      limit = std::min(limit, d);
      return true;
    });
    return limit;
  }

  void register_new_column_particles(std::size_t from) {
    // Column cells are placed before any fill particle, so ids are final.
    for (std::size_t i = from; i < tissue.particles.size(); ++i) {
      const Particle& p = tissue.particles[i];
      grid.insert(static_cast<int>(i), p.x_um, p.y_um, p.r_um);
    }
  }
};

Point myocyte_offset(double angle, double axial) {
  return {-axial * std::sin(angle), axial * std::cos(angle)};
}

bool myocyte_fits(const Workspace& ws, const ColumnTissueSpec& spec, double cx, double cy,
                  double angle) {
  for (int k = 0; k < kMyocyteParticles; ++k) {
    const Point o = myocyte_offset(angle, -kEnd + k * kParticleSpacing_um);
    const double x = cx + o.x, y = cy + o.y;
    if (x - kRadius < -1e-9 || x + kRadius > spec.width_um + 1e-9) return false;
    if (ws.overlaps(x, y, kRadius, kAllowedOverlap_um)) return false;
  }
  return true;
}

bool straight_cell_fits(const Workspace& ws, double x, double y0, bool fibroblast) {
  if (fibroblast) return !ws.overlaps(x, y0 + kRadius, kRadius, kAllowedOverlap_um);
  for (int k = 0; k < kMyocyteParticles; ++k)
    if (ws.overlaps(x, y0 + kRadius + k * kParticleSpacing_um, kRadius, kAllowedOverlap_um))
      return false;
  return true;
}

void build_column(Workspace& ws, const ColumnTissueSpec& spec, std::size_t c,
                  BuilderRandom& rng) {
  const double x = spec.column_x_um[c];
  const bool in_patch_x = spec.patch && spec.patch->contains_x(x);
  const InterstitialSettings& is = spec.interstitial;
  bool chained = false;           // the next cell touches the cell below at prev_top
  Point prev_top{0, 0};           // top particle of the cell below
  double y_next = 0;              // lowest point of the next cell
  for (;;) {
    bool in_patch = in_patch_x && spec.patch->contains_y(y_next);
    if (in_patch && spec.patch_interstitial) {
      if (!spec.column_in_patch[c]) {  // this fibre stops at the patch and resumes above it
        y_next = std::max(y_next, spec.patch->y1);
        chained = false;
        if (y_next >= spec.height_um) return;
        in_patch = false;  // a straight myocyte above the patch
      } else {
        bool placed = false, full = false;
        for (int attempt = 0; attempt < kRotationAttempts && !placed && !full; ++attempt) {
          const bool last = attempt == kRotationAttempts - 1;
          const double angle = last ? 0.0 : rng.uniform(-is.max_angle_rad, is.max_angle_rad);
          const double offset = last ? 0.0 : rng.uniform(-is.max_offset_um, is.max_offset_um);
          const Point bottom = myocyte_offset(angle, -kEnd);
          // Pushed to the right, a little at a time, until clear of the fibres
          // already placed (as the paper's DEM relaxation would push it).
          for (double push = 0; push <= kMaxPush_um && !placed; push += kPushStep_um) {
            const double cx = x + offset + push;
            double by;  // centre of the bottom particle
            if (chained) {
              const double dx = cx + bottom.x - prev_top.x;
              if (dx < -kRadius) continue;
              if (dx > kRadius) break;
              by = prev_top.y + std::sqrt(4 * kRadius * kRadius - dx * dx);
            } else {
              by = y_next + kRadius;
            }
            const double cy = by - bottom.y;
            const double top_y = cy - bottom.y;  // the top particle mirrors the bottom one
            if (top_y + kRadius > spec.height_um) {
              full = true;
              break;
            }
            if (!myocyte_fits(ws, spec, cx, cy, angle)) continue;
            const std::size_t from = ws.tissue.particles.size();
            add_myocyte(ws.tissue, cx, cy, angle);
            ws.register_new_column_particles(from);
            const Particle& top = ws.tissue.particles.back();
            prev_top = Point{top.x_um, top.y_um};
            chained = true;
            y_next = top.y_um + kRadius;
            placed = true;
          }
        }
        if (full) return;
        if (!placed) {  // blocked even when straight: move up and start a new chain
          chained = false;
          y_next += kParticleSpacing_um;
        }
        continue;
      }
    }
    // A straight cell, drawn fibroblast with the odds of its zone.
    const double odds = in_patch ? spec.fibroblast_odds_patch : spec.fibroblast_odds_outside;
    const bool fibroblast = odds > 0 && rng.chance(odds);
    const double length = fibroblast ? 2 * kRadius : kMyocyteLength_um;
    double y0 = y_next;
    if (chained && prev_top.x != x) {
      const double dx = x - prev_top.x;
      y0 = prev_top.y + std::sqrt(4 * kRadius * kRadius - dx * dx) - kRadius;
    }
    while (y0 + length <= spec.height_um && !straight_cell_fits(ws, x, y0, fibroblast)) {
      y0 += kScanStep_um;
      chained = false;
    }
    if (y0 + length > spec.height_um) return;
    const std::size_t from = ws.tissue.particles.size();
    if (fibroblast) add_round_fibroblast(ws.tissue, x, y0 + kRadius);
    else add_vertical_myocyte(ws.tissue, x, y0);
    ws.register_new_column_particles(from);
    y_next = y0 + length;
    prev_top = Point{x, y_next - kRadius};
    chained = true;
  }
}

void fill_patch(Workspace& ws, const Rect& region, const InterstitialSettings& is,
                BuilderRandom& rng) {
  const double area = (region.x1 - region.x0) * (region.y1 - region.y0);
  const auto attempts = static_cast<long long>(std::ceil(is.fill_attempts_per_um2 * area));
  const int first = static_cast<int>(ws.size());
  for (long long a = 0; a < attempts; ++a) {
    const double r = rng.uniform(is.r_min_um, is.r_max_um);
    const double x = rng.uniform(region.x0 + r, region.x1 - r);
    const double y = rng.uniform(region.y0 + r, region.y1 - r);
    if (ws.overlaps(x, y, r, 0.0)) continue;
    ws.fill.push_back({x, y, r, -1});
    ws.grid.insert(static_cast<int>(ws.size()) - 1, x, y, r);
  }
  // Grow every fill particle by U(1, growth_max), in random order, but never
  // into another particle: a particle whose growth is cut short touches its
  // neighbour exactly (and is bonded to it), so the fill stays overlap-free.
  std::vector<int> order(ws.fill.size());
  std::iota(order.begin(), order.end(), first);
  for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  for (int id : order) {
    Particle& p = ws.at(id);
    const double target = p.r_um * rng.uniform(1.0, is.growth_max);
    const double limit =
        is.growth_overlaps ? target : ws.free_radius(id, p.x_um, p.y_um, target);
    const double r = std::max(p.r_um, std::min(target, limit));
    if (r > p.r_um) {
      p.r_um = r;
      ws.grid.insert(id, p.x_um, p.y_um, r);
    }
  }
}

// Particle pairs of different cells that touch or overlap (ids into the workspace).
std::vector<std::pair<int, int>> touching_pairs(const Workspace& ws) {
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(ws.size());
  const int columns = static_cast<int>(ws.column_particles());
  std::vector<int> seen(n, -1);
  for (int i = 0; i < n; ++i) {
    const Particle& p = ws.at(i);
    ws.grid.visit(p.x_um, p.y_um, p.r_um + kMargin_um, [&](int j) {
      if (j <= i || seen[j] == i) return true;
      seen[j] = i;
      const Particle& q = ws.at(j);
      if (i < columns && j < columns && p.cell == q.cell) return true;  // one clump
      if (touching(p, q)) pairs.emplace_back(i, j);
      return true;
    });
  }
  return pairs;
}

struct UnionFind {
  std::vector<int> parent, size;
  explicit UnionFind(std::size_t n) : parent(n), size(n, 1) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(int a, int b, int max_size) {
    a = find(a);
    b = find(b);
    if (a == b || (max_size > 0 && size[a] + size[b] > max_size)) return;
    if (b < a) std::swap(a, b);
    parent[b] = a;
    size[a] += size[b];
  }
};

// The tissue without the cells outside the largest component of its cell graph.
Tissue keep_largest_component(const Tissue& t) {
  const CellComponents comps = cell_graph_components(t);
  if (comps.count() <= 1) return t;
  const int keep = comps.largest();
  Tissue out;
  std::vector<int> cell_map(t.cell_count(), -1), particle_map(t.particles.size(), -1);
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (comps.component[c] == keep) cell_map[c] = out.add_cell(t.type[c], t.x_um[c], t.y_um[c]);
  for (std::size_t i = 0; i < t.particles.size(); ++i) {
    const Particle& p = t.particles[i];
    if (cell_map[p.cell] >= 0)
      particle_map[i] = out.add_particle(cell_map[p.cell], p.x_um, p.y_um, p.r_um);
  }
  for (const Bond& b : t.bonds)
    if (particle_map[b.p] >= 0 && particle_map[b.q] >= 0) out.add_bond(particle_map[b.p], particle_map[b.q]);
  out.finalise();
  return out;
}

}  // namespace

std::vector<double> in_series_columns(double width_um) {
  std::vector<double> x;
  for (double c = kRadius; c + kRadius <= width_um + 1e-9; c += kColumnPitch_um) x.push_back(c);
  return x;
}

InterstitialSettings read_interstitial_settings(JsonReader& reader,
                                                const InterstitialSettings& d) {
  InterstitialSettings s;
  s.max_angle_rad =
      reader.number("max_rotation_deg", d.max_angle_rad * 180 / M_PI, 0, 45) * M_PI / 180;
  s.max_offset_um = reader.number("max_offset_um", d.max_offset_um, 0, 12.5);
  if (reader.has("fibroblast_radius_um")) {
    const json& r = reader.raw("fibroblast_radius_um");
    const std::string path = reader.path_of("fibroblast_radius_um");
    if (!r.is_array() || r.size() != 2 || !r[0].is_number() || !r[1].is_number())
      throw ManifestError(path, "expected [min, max] in um, got " + describe_json(r));
    s.r_min_um = r[0].get<double>();
    s.r_max_um = r[1].get<double>();
    if (!(s.r_min_um >= 0.1 && s.r_min_um <= s.r_max_um && s.r_max_um <= 8.0))
      throw ManifestError(path, "expected 0.1 <= min <= max <= 8 um, got " + describe_json(r));
  } else {
    s.r_min_um = d.r_min_um;
    s.r_max_um = d.r_max_um;
  }
  s.growth_max = reader.number("growth_max", d.growth_max, 1.0, 2.0);
  s.growth_overlaps =
      reader.text("growth", d.growth_overlaps ? "overlap" : "to_contact", {"to_contact", "overlap"}) ==
      "overlap";
  s.fill_attempts_per_um2 = reader.number("fill_attempts_per_um2", d.fill_attempts_per_um2, 0, 10);
  s.max_fibroblast_particles = static_cast<int>(
      reader.integer("max_fibroblast_particles", d.max_fibroblast_particles, 0, 1000000));
  s.drop_unconnected = !reader.boolean("keep_unconnected_fibroblasts", !d.drop_unconnected);
  return s;
}

double min_interstitial_spacing_um(const InterstitialSettings& s) {
  return 2 * kRadius + kEnd * std::sin(s.max_angle_rad) + s.max_offset_um;
}

Tissue build_column_tissue(const ColumnTissueSpec& spec, std::uint64_t seed) {
  BuilderRandom rng(seed);
  Workspace ws(spec);
  std::vector<double> column_top;
  for (std::size_t c = 0; c < spec.column_x_um.size(); ++c) {
    const std::size_t from = ws.tissue.particles.size();
    build_column(ws, spec, c, rng);
    double top = 0;
    for (std::size_t i = from; i < ws.tissue.particles.size(); ++i)
      top = std::max(top, ws.tissue.particles[i].y_um + ws.tissue.particles[i].r_um);
    column_top.push_back(top);
  }
  if (spec.patch && spec.patch_interstitial) {
    Rect region = *spec.patch;
    if (spec.fill_below_median_top && !column_top.empty()) {
      auto mid = column_top.begin() + column_top.size() / 2;
      std::nth_element(column_top.begin(), mid, column_top.end());
      region.y1 = std::min(region.y1, *mid);
    }
    fill_patch(ws, region, spec.interstitial, rng);
  }

  const auto pairs = touching_pairs(ws);
  const int columns = static_cast<int>(ws.column_particles());
  const int fills = static_cast<int>(ws.fill.size());

  // Fibroblasts of the fill: particles joined by bonds, in random bond order,
  // each at most max_fibroblast_particles particles.
  std::vector<int> fill_bonds;
  for (std::size_t b = 0; b < pairs.size(); ++b)
    if (pairs[b].first >= columns) fill_bonds.push_back(static_cast<int>(b));
  for (std::size_t i = fill_bonds.size(); i > 1; --i)
    std::swap(fill_bonds[i - 1], fill_bonds[rng.below(i)]);
  UnionFind groups(fills);
  for (int b : fill_bonds)
    groups.unite(pairs[b].first - columns, pairs[b].second - columns,
                 spec.interstitial.max_fibroblast_particles);

  // Provisional cell of every fill group (by its root), then cell-graph
  // components to find the groups connected to no myocyte.
  const int column_cells = static_cast<int>(ws.tissue.cell_count());
  std::vector<int> group_cell(fills, -1);
  int next_cell = column_cells;
  for (int f = 0; f < fills; ++f) {
    const int root = groups.find(f);
    if (group_cell[root] < 0) group_cell[root] = next_cell++;
  }
  auto provisional_cell = [&](int id) {
    return id < columns ? ws.tissue.particles[id].cell : group_cell[groups.find(id - columns)];
  };
  UnionFind graph(next_cell);
  for (const auto& [i, j] : pairs) graph.unite(provisional_cell(i), provisional_cell(j), 0);
  std::vector<char> has_myocyte(next_cell, 0);
  for (int c = 0; c < column_cells; ++c)
    if (ws.tissue.type[c] == CellType::myocyte) has_myocyte[graph.find(c)] = 1;

  // Append the kept fill groups as fibroblast cells, in order of their first particle.
  std::vector<int> final_cell(next_cell, -1);
  for (int c = 0; c < column_cells; ++c) final_cell[c] = c;
  std::vector<int> particle_index(ws.size(), -1);
  for (int i = 0; i < columns; ++i) particle_index[i] = i;
  std::vector<std::vector<int>> members(next_cell);
  for (int f = 0; f < fills; ++f) members[provisional_cell(columns + f)].push_back(f);
  for (int g = column_cells; g < next_cell; ++g) {
    if (members[g].empty()) continue;
    if (spec.interstitial.drop_unconnected && !has_myocyte[graph.find(g)]) continue;
    double area = 0, sx = 0, sy = 0;
    for (int f : members[g]) {
      const Particle& p = ws.fill[f];
      const double a = p.r_um * p.r_um;
      area += a;
      sx += a * p.x_um;
      sy += a * p.y_um;
    }
    const int cell = ws.tissue.add_cell(CellType::fibroblast, sx / area, sy / area);
    final_cell[g] = cell;
    for (int f : members[g]) {
      const Particle& p = ws.fill[f];
      particle_index[columns + f] = ws.tissue.add_particle(cell, p.x_um, p.y_um, p.r_um);
    }
  }
  for (const auto& [i, j] : pairs)
    if (particle_index[i] >= 0 && particle_index[j] >= 0)
      ws.tissue.add_bond(particle_index[i], particle_index[j]);
  ws.tissue.finalise();
  if (spec.patch_interstitial && spec.interstitial.drop_unconnected)
    return keep_largest_component(ws.tissue);
  return std::move(ws.tissue);
}

}  // namespace fibrodem
