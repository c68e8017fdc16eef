#include "measure/biomarkers.hpp"

#include "model/simd.hpp"
#include "model/work_split.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace fibrodem {

namespace {

std::vector<std::uint8_t> type_bytes(const std::vector<CellType>& types) {
  std::vector<std::uint8_t> bytes(types.size());
  std::transform(types.begin(), types.end(), bytes.begin(), [](CellType t) { return static_cast<std::uint8_t>(t); });
  return bytes;
}

}  // namespace

BiomarkerTracker::BiomarkerTracker(std::vector<CellType> types, std::vector<double> onsets,
                                   double from_ms, std::function<void(const BeatBiomarkers&)> on_beat)
    : types_(type_bytes(types)), onsets_(std::move(onsets)), from_ms_(from_ms),
      on_beat_(std::move(on_beat)), cells_(types_.size()), v_prev_(types_.size()), dvdt_max_(types_.size()),
      peak_(types_.size()), rmp_(types_.size()) {}

void BiomarkerTracker::reset_cell(std::size_t c, double rmp_mV) {
  cells_[c] = Cell{};
  rmp_[c] = rmp_mV;
  peak_[c] = -1e300;
  dvdt_max_[c] = -1e300;
}

void BiomarkerTracker::use_pre_upstroke_rmp(double window_ms, double gap_ms) {
  pre_upstroke_ = std::make_unique<PreUpstrokeWindow>(cells_.size(), window_ms, gap_ms);
  rmp_pre_.assign(cells_.size(), std::numeric_limits<double>::quiet_NaN());
}

void BiomarkerTracker::number_cells(std::vector<int> cell_numbers) {
  if (cell_numbers.size() != cells_.size())
    throw std::invalid_argument("BiomarkerTracker::number_cells: " + std::to_string(cell_numbers.size()) +
                                " numbers for " + std::to_string(cells_.size()) + " cells");
  cell_numbers_ = std::move(cell_numbers);
}

void BiomarkerTracker::start(double /*t_ms*/, const double* V) {
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    reset_cell(c, V[c]);
    v_prev_[c] = V[c];
  }
  dvdt_prev_.clear();
  // Without stimulus the run is one beat whose RMP is the initial V; with one,
  // beats open at the onsets.
  beat_ = onsets_.empty() ? 0 : -1;
}

void BiomarkerTracker::save(CheckpointFields& fields) const {
  // Cell is plain data: its bytes are its state (cell_bytes pins the layout).
  static_assert(std::is_trivially_copyable_v<Cell>);
  fields.put_integer("biomarkers.cell_bytes", static_cast<long long>(sizeof(Cell)));
  fields.put_bytes(kPerCellBytesField, cells_.data(), cells_.size() * sizeof(Cell));
  fields.put("biomarkers.v_prev", v_prev_);
  fields.put("biomarkers.dvdt_max", dvdt_max_);
  fields.put("biomarkers.peak", peak_);
  fields.put("biomarkers.rmp", rmp_);
  if (!dvdt_prev_.empty()) fields.put("biomarkers.dvdt_prev", dvdt_prev_);
  fields.put_integer("biomarkers.beat", beat_);
  fields.put_integer("biomarkers.next_onset", static_cast<long long>(next_onset_));
  if (pre_upstroke_) {
    pre_upstroke_->save(fields);
    fields.put("biomarkers.pre_upstroke.rmp", rmp_pre_);
  }
}

std::vector<std::string> BiomarkerTracker::per_cell_number_fields() {
  return {"biomarkers.v_prev", "biomarkers.dvdt_max", "biomarkers.peak", "biomarkers.rmp", "biomarkers.dvdt_prev",
          "biomarkers.pre_upstroke.rmp", PreUpstrokeWindow::kIntegralField};
}

void BiomarkerTracker::load(const CheckpointFields& fields) {
  if (fields.integer("biomarkers.cell_bytes") != static_cast<long long>(sizeof(Cell)))
    throw CheckpointError("its biomarker trackers were written by another build of fibrodem");
  fields.bytes(kPerCellBytesField, cells_.data(), cells_.size() * sizeof(Cell));  // (doubles and a byte: any bytes are valid)
  fields.read_into("biomarkers.v_prev", v_prev_);
  fields.read_into("biomarkers.dvdt_max", dvdt_max_);
  fields.read_into("biomarkers.peak", peak_);
  fields.read_into("biomarkers.rmp", rmp_);
  dvdt_prev_.clear();
  if (fields.has("biomarkers.dvdt_prev")) {
    dvdt_prev_.resize(cells_.size());
    fields.read_into("biomarkers.dvdt_prev", dvdt_prev_);
  }
  beat_ = static_cast<int>(fields.integer("biomarkers.beat"));
  next_onset_ = static_cast<std::size_t>(fields.integer("biomarkers.next_onset"));
  if (next_onset_ > onsets_.size()) throw CheckpointError("its biomarker trackers are past the scene's last beat");
  if (pre_upstroke_) {
    pre_upstroke_->load(fields);
    fields.read_into("biomarkers.pre_upstroke.rmp", rmp_pre_);
  }
}

void BiomarkerTracker::open_beat(double onset, double t_old, double t_new, const double* V) {
  close_beat();
  ++beat_;
  const double w = t_new > t_old ? std::clamp((onset - t_old) / (t_new - t_old), 0.0, 1.0) : 0.0;
  for (std::size_t c = 0; c < cells_.size(); ++c) reset_cell(c, v_prev_[c] + w * (V[c] - v_prev_[c]));
  std::fill(rmp_pre_.begin(), rmp_pre_.end(), std::numeric_limits<double>::quiet_NaN());
}

namespace {

// Time within a step [t0, t0 + h] at which V falls through `level`, with
// v0 >= level > v1. With the slopes d0, d1 at both ends (an integrator's own
// dV/dt) the crossing of the cubic Hermite interpolant, found by Newton's
// method kept inside the bracket: in late repolarisation V curves over CVODE's
// long steps, and the chord would cross late. Without them, the chord. (At a
// stimulus edge d0 is the slope before the edge; CVODE restarts there with
// tiny steps, so the cubic's error from it is negligible.)
double falling_crossing(double t0, double h, double v0, double v1, double d0, double d1, double level) {
  double theta = (v0 - level) / (v0 - v1);  // the chord's crossing
  if (!std::isfinite(d0) || !std::isfinite(d1)) return t0 + h * theta;
  // p(theta) - level on [0, 1], p the Hermite cubic.
  auto excess = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * v1 +
           (s3 - s2) * h * d1 - level;
  };
  auto slope = [&](double s) {
    const double s2 = s * s;
    return (6 * s2 - 6 * s) * v0 + (3 * s2 - 4 * s + 1) * h * d0 + (-6 * s2 + 6 * s) * v1 + (3 * s2 - 2 * s) * h * d1;
  };
  double lo = 0, hi = 1;  // excess(lo) >= 0 > excess(hi)
  for (int k = 0; k < 50 && hi - lo > 1e-14; ++k) {
    const double f = excess(theta);
    if (f == 0) break;
    (f > 0 ? lo : hi) = theta;
    const double df = slope(theta);
    const double next = theta - f / df;
    theta = df < 0 && next > lo && next < hi ? next : 0.5 * (lo + hi);  // Newton, else bisection
  }
  return t0 + h * theta;
}

// Where dV/dt peaks between samples: the vertex of the parabola through
// (t0, d0), (t1, d1), (t2, d2), t0 < t1 < t2, d1 the largest. As d1 >= d0, d2
// the vertex always lies within half a step of t1, so even where dV/dt has a
// kink (a stimulus edge) the time is no further off than the samples' own
// spacing. Only the time is taken: at a kink the parabola's height could
// overshoot, so max dV/dt stays the largest sample. Unchanged if the parabola
// does not open downwards.
void refine_peak_time(double t0, double d0, double t1, double d1, double t2, double d2, double& t_peak) {
  const double a = t0 - t1, b = t2 - t1;  // d = d1 + p u + q u^2, u = t - t1
  if (!(a < 0 && b > 0) || !std::isfinite(d0)) return;
  const double q = ((d2 - d1) / b - (d0 - d1) / a) / (b - a);
  const double p = (d0 - d1) / a - q * a;
  if (!(q < 0)) return;
  t_peak = t1 + std::clamp(-p / (2 * q), 0.5 * a, 0.5 * b);  // the clamp only guards round-off
}

}  // namespace

void BiomarkerTracker::step(double t_old, double t_new, const double* V, const double* dVdt) {
  // (V_prev is V at t_old for every cell: each step sets it, below.)
  if (pre_upstroke_) pre_upstroke_->add_step(t_old, t_new, v_prev_.data(), V);
  while (next_onset_ < onsets_.size() && onsets_[next_onset_] < t_new - 1e-9) {
    open_beat(onsets_[next_onset_], t_old, t_new, V);
    ++next_onset_;
  }
  if (!dVdt) return step_cells(t_old, t_new, V, 0, cells_.size());
  if (dvdt_prev_.empty()) dvdt_prev_.assign(cells_.size(), std::numeric_limits<double>::quiet_NaN());
  if (beat_ < 0) {
    std::copy(V, V + cells_.size(), v_prev_.begin());
    std::copy(dVdt, dVdt + cells_.size(), dvdt_prev_.begin());
    return;
  }
  for_each_cell(static_cast<long>(cells_.size()), [&](long c) { step_cell(c, t_old, t_new, V, dVdt); });
}

void BiomarkerTracker::step_cells(double t_old, double t_new, const double* V, std::size_t begin, std::size_t end) {
  if (beat_ >= 0) return step_lanes(t_old, t_new, V, begin, end);
  // Before the first beat only V moves on (dvdt_prev stays NaN without dV/dt).
  std::copy(V + begin, V + end, v_prev_.begin() + static_cast<std::ptrdiff_t>(begin));
}

void BiomarkerTracker::step_cell(std::size_t c, double t_old, double t_new, const double* V, const double* dVdt) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const double h = t_new - t_old;
  Cell& s = cells_[c];
  double &dvdt_max = dvdt_max_[c], &peak = peak_[c];
  const double slope = dVdt ? dVdt[c] : (V[c] - v_prev_[c]) / h;
  const double t_slope = dVdt ? t_new : t_old + 0.5 * h;
  if (slope > dvdt_max) {
    // The peak between samples is refined once the next one is in, from its
    // neighbours on the adjacent steps (the integrator's dV/dt at step ends,
    // or difference quotients, second order at step middles). A rising
    // upstroke reaches this function at every step (its slope keeps growing,
    // then V keeps rising to the peak), so both neighbours are seen. The
    // left one is the last sample if it was taken on the step just before
    // (the last largest, if that was it); it stays in the last sample's place.
    const bool left_known = s.slope_step_end == t_old;
    if (left_known && s.max_pending) s.slope_prev = dvdt_max, s.t_slope_prev = s.t_act;
    if (!left_known) s.slope_prev = slope, s.t_slope_prev = t_slope;
    s.max_pending = left_known;
    dvdt_max = slope;
    s.t_act = t_slope;
    if (pre_upstroke_) rmp_pre_[c] = pre_upstroke_->mean_before(c, t_slope);
  } else {
    if (s.max_pending && s.slope_step_end == t_old)  // the right neighbour is the step just after
      refine_peak_time(s.t_slope_prev, s.slope_prev, s.t_act, dvdt_max, t_slope, slope, s.t_act);
    s.max_pending = 0;
    s.slope_prev = slope;
    s.t_slope_prev = t_slope;
  }
  s.slope_step_end = t_new;
  if (V[c] > peak) {
    peak = V[c];
    s.cross50 = s.cross90 = -1;  // a new peak: repolarisation not yet seen
  } else {
    const double amplitude = peak - rmp_[c];
    const double d0 = dvdt_prev_.empty() ? kNaN : dvdt_prev_[c];
    const double d1 = dVdt ? dVdt[c] : kNaN;
    auto crossing = [&](double fraction, double& t_cross) {
      const double level = peak - fraction * amplitude;
      if (v_prev_[c] >= level && V[c] < level) t_cross = falling_crossing(t_old, h, v_prev_[c], V[c], d0, d1, level);
    };
    crossing(0.5, s.cross50);
    crossing(0.9, s.cross90);
  }
  v_prev_[c] = V[c];
  if (!dvdt_prev_.empty()) dvdt_prev_[c] = dVdt ? dVdt[c] : kNaN;
}

void BiomarkerTracker::step_lanes(double t_old, double t_new, const double* V, std::size_t begin,
                                  std::size_t end) {
  using simd::Real;
  const double h = t_new - t_old;
  // A margin on the levels: step_cell may compute them with a fused
  // multiply-add, a bit apart from these; near a level, step_cell decides.
  constexpr double kLevelMargin_mV = 1e-9;
  for (std::size_t c = begin; c < end; c += simd::kLanes) {
    const std::size_t n = std::min(simd::kLanes, end - c);
    const Real v = simd::load(V + c, n), v_prev = simd::load(v_prev_.data() + c, n);
    const Real peak = simd::load(peak_.data() + c, n), amplitude = peak - simd::load(rmp_.data() + c, n);
    const Real level50 = peak - 0.5 * amplitude, level90 = peak - 0.9 * amplitude;
    const auto near = [&](const Real& level) {
      return (v_prev >= level - kLevelMargin_mV) & (v < level + kLevelMargin_mV);
    };
    const auto busy = ((v - v_prev) / h > simd::load(dvdt_max_.data() + c, n)) | (v > peak) | near(level50) |
                      near(level90);
    if (!xsimd::any(busy)) {  // only V moves on (dvdt_prev stays NaN without dV/dt)
      simd::store(v_prev_.data() + c, v, n);
      continue;
    }
    alignas(64) bool lane_busy[simd::kLanes];
    busy.store_aligned(lane_busy);
    for (std::size_t i = 0; i < n; ++i) {
      if (lane_busy[i]) step_cell(c + i, t_old, t_new, V, nullptr);
      else v_prev_[c + i] = V[c + i];
    }
  }
}

void BiomarkerTracker::close_beat() {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (beat_ < 0) return;
  const double onset = onsets_.empty() ? 0.0 : onsets_[beat_];
  if (onset + 1e-9 < from_ms_) return;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const Cell& s = cells_[c];
    BeatBiomarkers b;
    b.cell = cell_numbers_.empty() ? static_cast<int>(c) : cell_numbers_[c];
    b.type = static_cast<CellType>(types_[c]);
    b.beat = beat_;
    if (peak_[c] - rmp_[c] >= firing_rise_mV(b.type)) {
      b.activation_ms = s.t_act;
      b.rmp_mV = pre_upstroke_ ? rmp_pre_[c] : rmp_[c];
      b.apo_mV = peak_[c];
      b.dvdt_max_mV_per_ms = dvdt_max_[c];
      if (s.cross50 >= 0) b.apd50_ms = s.cross50 - s.t_act;
      if (s.cross90 >= 0) b.apd90_ms = s.cross90 - s.t_act;
    } else {
      // Not fired: the largest dV/dt of a cell at rest is noise, and its
      // "APD" the fall after a drift; only the onset V is a measurement (a
      // pre-upstroke RMP needs an upstroke).
      b.activation_ms = b.apo_mV = b.dvdt_max_mV_per_ms = kNaN;
      b.rmp_mV = pre_upstroke_ ? kNaN : rmp_[c];
    }
    on_beat_(b);
  }
}

void BiomarkerTracker::finish() {
  close_beat();
  beat_ = -1;
}

}  // namespace fibrodem
