#include "stimulus/stimulus.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "util/json_reader.hpp"

namespace fibrodem {

namespace {
// Whether a cell centred at (x, y) lies in the target's region (edges
// included, with a 1e-9 um tolerance: a cell exactly on an edge given in mm
// is in); box is the tissue's bounds_um(), taken once for all cells.
bool region_contains(const StimulusTarget& target, const std::array<double, 4>& box, double x, double y) {
  constexpr double kEdge_um = 1e-9;
  switch (target.shape) {
    case StimulusTarget::Shape::fractions: {
      const double w = box[1] - box[0], h = box[3] - box[2];
      const double fx = w > 0 ? (x - box[0]) / w : 0.5;
      const double fy = h > 0 ? (y - box[2]) / h : 0.5;
      return fx >= target.x_min_frac && fx <= target.x_max_frac && fy >= target.y_min_frac &&
             fy <= target.y_max_frac;
    }
    case StimulusTarget::Shape::rect_mm:
      return x >= 1000 * target.x_min_mm - kEdge_um && x <= 1000 * target.x_max_mm + kEdge_um &&
             y >= 1000 * target.y_min_mm - kEdge_um && y <= 1000 * target.y_max_mm + kEdge_um;
    case StimulusTarget::Shape::circle_mm: {
      const double dx = x - 1000 * target.center_x_mm, dy = y - 1000 * target.center_y_mm;
      return std::hypot(dx, dy) <= 1000 * target.radius_mm + kEdge_um;
    }
  }
  return false;
}

std::vector<int> resolve_target(const StimulusTarget& target, const Tissue& tissue,
                                const std::string& path) {
  std::vector<int> cells;
  const int n = static_cast<int>(tissue.cell_count());
  switch (target.kind) {
    case StimulusTarget::Kind::cell_type:
      tissue.for_each_type([&](int c, CellType t) {
        if (t == target.type) cells.push_back(c);
      });
      if (cells.empty())
        throw ManifestError(path + ".target", std::string("the tissue has no ") +
                                                  cell_type_name(target.type) + " to stimulate");
      break;
    case StimulusTarget::Kind::cells:
      for (std::size_t i = 0; i < target.cells.size(); ++i) {
        if (target.cells[i] >= n)
          throw ManifestError(index_path(path + ".target", i),
                              "cell " + std::to_string(target.cells[i]) + " does not exist (the tissue has " +
                                  std::to_string(n) + " cells, 0.." + std::to_string(n - 1) + ")");
        cells.push_back(target.cells[i]);
      }
      break;
    case StimulusTarget::Kind::region: {
      // (Every cell, which a rank of a split run may take from the
      // builder: Tissue::for_each_cell.)
      const auto box = tissue.bounds_um();
      tissue.for_each_cell([&](int c, CellType t, double x, double y) {
        if (!region_contains(target, box, x, y)) return;
        if (target.region_type && t != *target.region_type) return;
        cells.push_back(c);
      });
      if (cells.empty()) {
        throw ManifestError(path + ".target",
                            fmt::format("this region contains no cell{} (the tissue spans x {:g}..{:g} mm, "
                                        "y {:g}..{:g} mm)",
                                        target.region_type ? std::string(" of type ") + cell_type_name(*target.region_type) : "",
                                        box[0] / 1000, box[1] / 1000, box[2] / 1000, box[3] / 1000));
      }
      break;
    }
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}
}  // namespace

bool PulseTrain::on(double t) const {
  const double since = t - start_ms;
  if (since < -kTimeEpsilon_ms) return false;
  long long k = 0;
  if (period_ms > 0) k = static_cast<long long>(std::floor((since + kTimeEpsilon_ms) / period_ms));
  if (k >= count) return false;
  const double in_pulse = since - static_cast<double>(k) * period_ms;
  return in_pulse >= -kTimeEpsilon_ms && in_pulse < duration_ms - kTimeEpsilon_ms;
}

Stimulus::Stimulus(const std::vector<StimulusSpec>& specs, const Tissue& tissue) {
  for (const auto& s : specs) {
    std::vector<int> cells = resolve_target(s.target, tissue, s.path);
    trains_.push_back({cells, s.start_ms, s.duration_ms, s.amplitude_pA, s.period_ms, s.count, cells});
  }
}

void Stimulus::add_current(double t, double* i_ext) const {
  for (const auto& train : trains_)
    if (train.on(t))
      for (int c : train.applied_to) i_ext[c] += train.amplitude_pA;
}

void Stimulus::clear_current(double* i_ext) const {
  for (const auto& train : trains_)
    for (int c : train.applied_to) i_ext[c] = 0.0;
}

void Stimulus::hold_only(const CellNumbering& numbering) {
  for (auto& train : trains_) {
    train.applied_to.clear();
    for (int c : train.cells)
      if (numbering.owns(c)) train.applied_to.push_back(static_cast<int>(numbering.held_cell(c)));
    train.applied_to.shrink_to_fit();
  }
}

bool Stimulus::on(double t) const {
  for (const auto& train : trains_)
    if (train.on(t)) return true;
  return false;
}

double Stimulus::next_edge_after(double t) const {
  double next = std::numeric_limits<double>::infinity();
  for (const auto& train : trains_) {
    long long k = 0;
    if (train.period_ms > 0 && t > train.start_ms)
      k = static_cast<long long>(std::floor((t - train.start_ms) / train.period_ms));
    for (long long j = std::max(0LL, k - 1); j < std::min(train.count, k + 2); ++j) {
      const double on = train.start_ms + static_cast<double>(j) * train.period_ms;
      for (double edge : {on, on + train.duration_ms})
        if (edge > t + kTimeEpsilon_ms) next = std::min(next, edge);
    }
  }
  return next;
}

std::vector<double> Stimulus::onsets(double until) const {
  std::vector<double> times;
  for (const auto& train : trains_)
    for (long long k = 0; k < train.count; ++k) {
      const double on = train.start_ms + static_cast<double>(k) * train.period_ms;
      if (on > until) break;
      times.push_back(on);
      if (train.period_ms <= 0) break;
    }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end(),
                          [](double x, double y) { return std::abs(x - y) < kTimeEpsilon_ms; }),
              times.end());
  return times;
}

double Stimulus::shortest_pulse_ms() const {
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& train : trains_) shortest = std::min(shortest, train.duration_ms);
  return shortest;
}

}  // namespace fibrodem
