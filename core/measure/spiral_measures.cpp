#include "measure/spiral_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/csv_writer.hpp"

namespace fibrodem {

namespace {
using Point2 = std::array<double, 2>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// The largest distance between two of the points (over the hull's vertices:
// the farthest pair of a set lies on its hull).
double diameter(const std::vector<Point2>& hull) {
  double most = 0;
  for (std::size_t i = 0; i < hull.size(); ++i)
    for (std::size_t j = i + 1; j < hull.size(); ++j)
      most = std::max(most, std::hypot(hull[j][0] - hull[i][0], hull[j][1] - hull[i][1]));
  return most;
}

// The median (the upper of two middles, as the re-entry summary's).
double upper_median(std::vector<double>& values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

struct Window {
  double x = 0, y = 0, t = 0;
};

// The mean position and time of the trajectory's points inside (from, to)
// with the ends given as open or closed.
Window mean_over(const std::vector<SingularityTrack::Point>& path, double from, double to, bool first) {
  Window w;
  int n = 0;
  for (const auto& p : path) {
    const bool in = first ? (p.t_ms >= from && p.t_ms < to) : (p.t_ms > from && p.t_ms <= to);
    if (!in) continue;
    w.x += p.x_mm, w.y += p.y_mm, w.t += p.t_ms;
    ++n;
  }
  if (n > 0) w.x /= n, w.y /= n, w.t /= n;
  return w;
}

// The rotation centre's displacement: the mean tip positions over the first
// and the last rotation (or half-life), and the speed between them.
void measure_drift(const SingularityTrack& track, SpiralMeasures& m) {
  const auto& path = track.trajectory;
  if (path.size() < 2 || m.lifetime_ms <= 0) {
    m.drift_mm = 0;
    m.drift_speed_mm_per_s = kNaN;
    return;
  }
  const double window = std::isfinite(m.period_ms) ? std::min(m.period_ms, m.lifetime_ms / 2) : m.lifetime_ms / 2;
  const Window a = mean_over(path, m.birth_ms, m.birth_ms + window, true);
  const Window b = mean_over(path, m.death_ms - window, m.death_ms, false);
  m.drift_mm = std::hypot(b.x - a.x, b.y - a.y);
  m.drift_speed_mm_per_s = b.t > a.t ? m.drift_mm / ((b.t - a.t) / 1000.0) : kNaN;
}
}  // namespace

std::vector<Point2> convex_hull(std::vector<Point2> p) {
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Point2> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);  // the last point is the first
  return hull;
}

double polygon_area(const std::vector<Point2>& polygon) {
  double twice = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice += a[0] * b[1] - b[0] * a[1];
  }
  return twice / 2;
}

double rotation_period_ms(const SingularityTrack& track, const Tissue& tissue,
                          const std::vector<std::vector<double>>& activations_ms) {
  if (track.trajectory.empty()) return kNaN;
  double x = 0, y = 0, reach = 0;
  for (const auto& p : track.trajectory) x += p.x_mm, y += p.y_mm;
  x /= track.trajectory.size(), y /= track.trajectory.size();
  for (const auto& p : track.trajectory) reach = std::max(reach, std::hypot(p.x_mm - x, p.y_mm - y) + p.reach_mm);
  reach += kTipNeighbourhood_mm;
  std::vector<double> per_cell, intervals;
  for (std::size_t c = 0; c < tissue.cell_count() && c < activations_ms.size(); ++c) {
    if (std::hypot(tissue.x_um[c] / 1000 - x, tissue.y_um[c] / 1000 - y) > reach) continue;
    intervals.clear();
    const auto& a = activations_ms[c];
    for (std::size_t k = 1; k < a.size(); ++k)
      if (a[k - 1] >= track.birth_ms && a[k] <= track.death_ms) intervals.push_back(a[k] - a[k - 1]);
    if (!intervals.empty()) per_cell.push_back(upper_median(intervals));
  }
  return per_cell.empty() ? kNaN : upper_median(per_cell);
}

SpiralMeasures spiral_measures(const SingularityTrack& track, double period_ms) {
  SpiralMeasures m;
  m.id = track.id;
  m.chirality = track.chirality;
  m.birth_ms = track.birth_ms;
  m.death_ms = track.death_ms;
  m.lifetime_ms = track.death_ms - track.birth_ms;
  m.period_ms = period_ms > 0 ? period_ms : kNaN;
  m.rotations = std::isfinite(m.period_ms) ? m.lifetime_ms / m.period_ms : 0.0;
  m.rotor = m.rotations >= 1;
  std::vector<Point2> points;
  points.reserve(track.trajectory.size());
  for (const auto& p : track.trajectory) {
    points.push_back({p.x_mm, p.y_mm});
    m.x_mm += p.x_mm, m.y_mm += p.y_mm;
  }
  if (!points.empty()) m.x_mm /= points.size(), m.y_mm /= points.size();
  const auto hull = convex_hull(std::move(points));
  m.meander_extent_mm = diameter(hull);
  m.meander_area_mm2 = hull.size() >= 3 ? polygon_area(hull) : 0.0;
  measure_drift(track, m);
  return m;
}

void write_spiral_measures_csv(const std::filesystem::path& file, const std::vector<SpiralMeasures>& spirals) {
  CsvWriter csv(file, {"id", "chirality", "birth_ms", "death_ms", "lifetime_ms", "rotations", "period_ms", "rotor",
                       "x_mm", "y_mm", "drift_mm", "drift_speed_mm_per_s", "meander_extent_mm", "meander_area_mm2"});
  for (const auto& s : spirals) {
    csv.cell(static_cast<long long>(s.id)).cell(static_cast<long long>(s.chirality)).cell(s.birth_ms)
        .cell(s.death_ms).cell(s.lifetime_ms).cell(s.rotations).cell(format_number_or_empty(s.period_ms))
        .cell(static_cast<long long>(s.rotor)).cell(s.x_mm).cell(s.y_mm).cell(s.drift_mm)
        .cell(format_number_or_empty(s.drift_speed_mm_per_s)).cell(s.meander_extent_mm).cell(s.meander_area_mm2);
    csv.end_row();
  }
  csv.flush();
}

}  // namespace fibrodem
