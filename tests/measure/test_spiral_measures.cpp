// Spiral measures of a phase singularity's track (period, lifetime, drift,
// meander) and the driver measures of AF mapping (PS density, rotor time,
// the highest dominant frequency), on paths and fields whose answers are
// known in closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "measure/beat_activations.hpp"
#include "measure/dominant_frequency.hpp"
#include "measure/driver_maps.hpp"
#include "measure/reentry.hpp"
#include "measure/spiral_measures.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
constexpr double kPi = std::numbers::pi;

// A track of the tip at position(t) every dt_ms from 0 to end_ms.
SingularityTrack track_of(const std::function<std::array<double, 2>(double t_ms)>& position, double dt_ms,
                          double end_ms, int chirality = 1) {
  SingularityTrack track;
  track.chirality = chirality;
  const int steps = static_cast<int>(std::lround(end_ms / dt_ms));
  for (int k = 0; k <= steps; ++k) {
    const double t = k * dt_ms;
    const auto [x, y] = position(t);
    track.trajectory.push_back({t, x, y});
  }
  track.birth_ms = track.trajectory.front().t_ms;
  track.death_ms = track.trajectory.back().t_ms;
  return track;
}

// An n x n square grid of cells spacing_um apart, joined to their 4 neighbours.
Tissue grid(int n, double spacing_um) {
  Tissue t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) t.add_cell(CellType::myocyte, i * spacing_um, j * spacing_um);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) t.cell_edges.emplace_back(j * n + i, j * n + i + 1);
      if (j + 1 < n) t.cell_edges.emplace_back(j * n + i, (j + 1) * n + i);
    }
  t.finalise();
  return t;
}
}  // namespace

TEST_CASE("a tip on a circle: meander extent 2r, the area of its polygon, no drift, its period") {
  // Radius 0.8 mm about (3.1, 2.7) mm, period 200 ms sampled every 2 ms
  // (100 points a turn), three turns.
  const double r = 0.8, T = 200, x0 = 3.1, y0 = 2.7;
  const auto track = track_of([&](double t) {
    return std::array{x0 + r * std::cos(2 * kPi * t / T), y0 + r * std::sin(2 * kPi * t / T)};
  }, 2.0, 3 * T);
  const SpiralMeasures m = spiral_measures(track, T);
  CHECK(m.lifetime_ms == 3 * T);  // the first and last samples' times, exactly
  CHECK(m.rotations == doctest::Approx(3).epsilon(1e-12));
  CHECK(m.period_ms == T);
  CHECK(m.rotor);
  // 100 samples a turn hold antipodal pairs: the diameter is 2r.
  CHECK(m.meander_extent_mm == doctest::Approx(2 * r).epsilon(1e-12));
  // The hull is the regular 100-gon inscribed in the circle, area
  // (n / 2) r^2 sin(2 pi / n); pi r^2 less (2 pi / n)^2 / 6 of it (6.6e-4).
  const double n = 100;
  CHECK(m.meander_area_mm2 == doctest::Approx(n / 2 * r * r * std::sin(2 * kPi / n)).epsilon(1e-12));
  CHECK(m.meander_area_mm2 == doctest::Approx(kPi * r * r).epsilon(1e-3));
  // The mean position over the first turn and over the last is the centre.
  CHECK(m.drift_mm < 1e-12);
  CHECK(m.drift_speed_mm_per_s < 1e-10);
  // The mean of the 301 positions counts the start (x0 + r, y0) twice.
  CHECK(m.x_mm == doctest::Approx(x0 + r / 301).epsilon(1e-12));
  CHECK(m.y_mm == doctest::Approx(y0).epsilon(1e-12));
}

TEST_CASE("a tip at constant velocity drifts at that speed, with or without a rotation period") {
  // v = (3, 4) mm/s (5 mm/s) for 500 ms sampled every 1 ms: the path is a
  // segment 2.5 mm long, of no area.
  const auto position = [](double t) { return std::array{1.0 + 0.003 * t, -2.0 + 0.004 * t}; };
  for (double period : {200.0, std::nan("")}) {  // windows of 200 ms; none: half-lives
    CAPTURE(period);
    const SpiralMeasures m = spiral_measures(track_of(position, 1.0, 500), period);
    CHECK(m.drift_speed_mm_per_s == doctest::Approx(5).epsilon(1e-9));
    CHECK(m.meander_extent_mm == doctest::Approx(2.5).epsilon(1e-12));
    CHECK(m.meander_area_mm2 < 1e-12);  // collinear but for rounding
    // Window means at 99.5 and 400.5 ms (period 200), or 124.5 and 375.5 ms (half-lives).
    CHECK(m.drift_mm == doctest::Approx(5e-3 * (period > 0 ? 301 : 251)).epsilon(1e-9));
  }
  // Without a period there is no rotation, and no rotor; with one longer
  // than the life, a fraction of a turn.
  const SpiralMeasures still = spiral_measures(track_of(position, 1.0, 500), std::nan(""));
  CHECK(std::isnan(still.period_ms));
  CHECK(still.rotations == 0);
  CHECK_FALSE(still.rotor);
  const SpiralMeasures part = spiral_measures(track_of(position, 1.0, 500), 625);
  CHECK(part.rotations == 0.8);
  CHECK_FALSE(part.rotor);
  // A PS seen in one sample: no life, no drift speed.
  const SpiralMeasures once = spiral_measures(track_of(position, 1.0, 0), std::nan(""));
  CHECK(once.lifetime_ms == 0);
  CHECK(once.drift_mm == 0);
  CHECK(std::isnan(once.drift_speed_mm_per_s));
}

TEST_CASE("the rotation period is the cycle length of the cells around the tip, within its life") {
  // A tip at (1, 1) mm for 100-700 ms on a 41 x 41 grid 0.1 mm apart. The
  // cells within 1 mm (a fifth of them) activate every 150 ms through the
  // life (and once 90 ms before it, which does not count); the others,
  // the majority, every 400 ms.
  const Tissue t = grid(41, 100);
  SingularityTrack track;
  track.trajectory = {{100, 1.0, 1.0}, {700, 1.0, 1.0}};
  track.birth_ms = 100, track.death_ms = 700;
  std::vector<std::vector<double>> activations(t.cell_count());
  std::size_t near = 0;
  for (std::size_t c = 0; c < t.cell_count(); ++c) {
    const bool around = std::hypot(t.x_um[c] / 1000 - 1.0, t.y_um[c] / 1000 - 1.0) <= kTipNeighbourhood_mm;
    near += around;
    const double every = around ? 150 : 400;
    activations[c] = {-80, 10};
    for (double a = 100 + c % 7; a <= 700; a += every) activations[c].push_back(a);
  }
  REQUIRE(near > 0);
  REQUIRE(2 * near < t.cell_count());
  CHECK(rotation_period_ms(track, t, activations) == doctest::Approx(150));
  // A life shorter than a cycle: no cell activates twice in it.
  track.death_ms = 200;
  CHECK(std::isnan(rotation_period_ms(track, t, activations)));
}

TEST_CASE("a phase singularity in a hole takes its period from the cells around the hole") {
  // A PS in a hole is placed at the hole's centroid, possibly far from every
  // cell: its reach (centroid to farthest rim cell) widens "around the tip"
  // by as much. A tip at (2, 2) mm on a 41 x 41 grid 0.1 mm apart: cells
  // within 1 mm activate every 150 ms, those 1-1.5 mm away every 120 ms (the
  // more of the two: a ring of 3.9 mm^2 against a disk of 3.1), the rest
  // (8.9 mm^2) every 400 ms. With reach 0.5 mm the median is the ring's.
  const Tissue t = grid(41, 100);
  std::vector<std::vector<double>> activations(t.cell_count());
  for (std::size_t c = 0; c < t.cell_count(); ++c) {
    const double r = std::hypot(t.x_um[c] / 1000 - 2.0, t.y_um[c] / 1000 - 2.0);
    const double every = r <= 1.0 ? 150 : r <= 1.5 ? 120 : 400;
    for (double a = 100 + c % 7; a <= 700; a += every) activations[c].push_back(a);
  }
  SingularityTrack track;
  track.birth_ms = 100, track.death_ms = 700;
  track.trajectory = {{100, 2.0, 2.0}, {700, 2.0, 2.0}};
  CHECK(rotation_period_ms(track, t, activations) == doctest::Approx(150));
  track.trajectory = {{100, 2.0, 2.0, 0.5}, {700, 2.0, 2.0, 0.5}};
  CHECK(rotation_period_ms(track, t, activations) == doctest::Approx(120));
}

TEST_CASE("the convex hull of a square with points inside it is the square") {
  const auto hull = convex_hull({{0, 0}, {2, 0}, {1, 1}, {2, 2}, {0, 2}, {1, 0}, {0.5, 1.5}, {2, 2}});
  CHECK(hull.size() == 4);  // (1, 0) lies on an edge: left out
  CHECK(polygon_area(hull) == 4.0);
}

TEST_CASE("a rotating spiral-like field: one phase singularity, its period and chirality") {
  // V = V* + 40 cos(omega t - s theta - k rho) about (x0, y0): a spiral of
  // wavelength 2 pi / k turning counter-clockwise for s = +1. With tau a
  // quarter period the embedding phase is omega t - s theta - k rho, whose
  // charge around the centre is -s. Every cell crosses V* upward once a
  // period, 200 ms: the cycle length of the cells around the tip.
  const Tissue t = grid(21, 100);
  const double x0 = 1033, y0 = 987, period = 200, omega = 2 * kPi / period, k = 2 * kPi / 2000, V_star = -50;
  const ReentrySettings s{.every_ms = 5, .from_ms = 0, .tau_ms = period / 4, .V_star_mV = V_star, .link_mm = 1,
                          .ps_density_bin_mm = 0.5};
  for (int turn : {1, -1}) {
    CAPTURE(turn);
    VoltageFrames frames(t.cell_count());
    for (double time = 0; time <= 995 + 1e-9; time += 5) {
      std::vector<double> V(t.cell_count());
      for (std::size_t c = 0; c < V.size(); ++c) {
        const double dx = t.x_um[c] - x0, dy = t.y_um[c] - y0;
        V[c] = V_star + 40 * std::cos(omega * time - turn * std::atan2(dy, dx) - k * std::hypot(dx, dy));
      }
      frames.add(time, V);
    }
    const auto dir = testing::scratch_dir("spiral_field");
    const json r = analyse_reentry(t, frames, s, {0}, {}, dir);
    CAPTURE(r.dump());
    REQUIRE(r["phase_singularities_tracked"] == 1);
    const json& spiral = r["longest_track"];
    CHECK(spiral["chirality"] == -turn);
    // Seen from the first sample with a delayed one (50 ms) to the last (995 ms).
    CHECK(spiral["lifetime_ms"].get<double>() == doctest::Approx(945));
    // Each cell's crossings lie 40 samples apart at the same offset from them.
    CHECK(spiral["period_ms"].get<double>() == doctest::Approx(period).epsilon(1e-9));
    CHECK(spiral["rotations"].get<double>() == doctest::Approx(945 / period).epsilon(1e-9));
    CHECK(spiral["rotor"] == true);
    // The centre stays in one triangle: no drift, no meander.
    CHECK(spiral["drift_mm"].get<double>() == 0);
    CHECK(spiral["meander_extent_mm"].get<double>() == 0);
    CHECK(r["rotors"] == 1);
    CHECK(r["rotor_time_fraction"].get<double>() == 1.0);
    // 190 samples with one PS, 5 ms each: 0.95 PS-s, all in the bin of the
    // centre (0.5 mm bins: 0.0025 cm2).
    CHECK(r["phase_singularity_seconds"].get<double>() == doctest::Approx(0.95));
    CHECK(r["ps_density_max_per_cm2"].get<double>() == doctest::Approx(0.95 / 0.0025));
    const auto tracks = testing::csv_rows(dir / "phase_singularity_tracks.csv");
    REQUIRE(tracks.size() == 2);
    CHECK(tracks[0][6] == "period_ms");
    CHECK(std::stod(tracks[1][6]) == spiral["period_ms"].get<double>());
    double total = 0;
    const auto density = testing::csv_rows(dir / "phase_singularity_density.csv");
    CHECK(density.size() == 1 + 4 * 4);  // a 2 x 2 mm sheet in 0.5 mm bins
    for (std::size_t row = 1; row < density.size(); ++row) total += std::stod(density[row][3]) * 0.0025;
    CHECK(total == doctest::Approx(0.95));
  }
}

TEST_CASE("PS density integrates to the PS-seconds of the tracks, each in its bin") {
  // Bounds 3 x 2 mm in 0.5 mm bins (6 x 4); 1 ms a sample.
  SingularityTrack a, b;
  a.trajectory = {{0, 0.25, 0.25}, {1, 0.3, 0.3}, {2, 0.26, 0.2}};  // bin (0, 0), 3 samples
  b.trajectory = {{5, 2.9, 1.9}, {6, 3.5, 2.5}};  // bin (5, 3), the second outside: counted at the edge
  const PsDensityGrid g = ps_density({a, b}, {0, 3, 0, 2}, 0.5, 1.0);
  REQUIRE(g.nx == 6);
  REQUIRE(g.ny == 4);
  CHECK(g.ps_seconds[0] == doctest::Approx(3e-3));
  CHECK(g.ps_seconds[3 * 6 + 5] == doctest::Approx(2e-3));
  double total = 0;
  for (double s : g.ps_seconds) total += s;
  CHECK(total == doctest::Approx(5e-3));  // 5 samples x 1 ms
  CHECK(g.bin_area_cm2() == doctest::Approx(0.0025));
  CHECK_THROWS_AS(ps_density({a}, {0, 3, 0, 2}, 0.0, 1.0), std::invalid_argument);
}

TEST_CASE("the fraction of time with a rotor counts the samples in which one is alive") {
  // Samples 0, 1, ..., 99 ms. Rotors alive 10-29 and 20-49 ms cover 10-49
  // ms: 40 samples; a PS that is no rotor (alive throughout) adds none.
  std::vector<double> times;
  for (int k = 0; k < 100; ++k) times.push_back(k);
  auto spiral = [](double birth, double death, bool rotor) {
    SpiralMeasures m;
    m.birth_ms = birth, m.death_ms = death, m.rotor = rotor;
    return m;
  };
  CHECK(rotor_time_fraction({spiral(10, 29, true), spiral(0, 99, false), spiral(20, 49, true)}, times) == 0.4);
  CHECK(rotor_time_fraction({spiral(0, 99, false)}, times) == 0.0);
  CHECK(std::isnan(rotor_time_fraction({}, {})));
}

TEST_CASE("the highest dominant frequency site is the centroid of the cells at the highest frequency") {
  const Tissue t = grid(3, 100);
  std::vector<double> hz(t.cell_count(), 5.0);
  hz[0] = hz[2] = 8.0;  // (0, 0) and (0.2, 0) mm
  hz[4] = std::nan("");
  const HighestFrequencySite site = highest_frequency_site(t, hz);
  CHECK(site.frequency_hz == 8.0);
  CHECK(site.cells == 2);
  CHECK(site.x_mm == doctest::Approx(0.1));
  CHECK(site.y_mm == 0.0);
  const HighestFrequencySite none = highest_frequency_site(t, std::vector<double>(t.cell_count(), std::nan("")));
  CHECK(std::isnan(none.frequency_hz));
  CHECK(none.cells == 0);
}

TEST_CASE("the dominant frequency in two bands from one spectrum") {
  // 2 Hz at amplitude 40 and 7 Hz at 20, sampled every 2 ms for 2 s: the
  // band 1-30 Hz finds 2 Hz, the clinical 3-12 Hz 7 Hz; the band alone
  // gives the same bits as with the other beside it.
  const std::size_t samples = 1000;
  std::vector<float> frames(samples);
  for (std::size_t m = 0; m < samples; ++m) {
    const double t_s = m * 0.002;
    frames[m] = static_cast<float>(-40 + 40 * std::sin(2 * kPi * 2 * t_s) + 20 * std::sin(2 * kPi * 7 * t_s));
  }
  const auto both = dominant_frequencies(frames, 1, samples, 2.0, {{1, 30}, {3, 12}});
  REQUIRE(both.size() == 2);
  CHECK(both[0].per_cell_hz[0] == doctest::Approx(2.0));
  CHECK(both[1].per_cell_hz[0] == doctest::Approx(7.0));
  CHECK(dominant_frequencies(frames, 1, samples, 2.0, 1, 30).per_cell_hz[0] == both[0].per_cell_hz[0]);
  CHECK(dominant_frequencies(frames, 1, samples, 2.0, 3, 12).per_cell_hz[0] == both[1].per_cell_hz[0]);
}
