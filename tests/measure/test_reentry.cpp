// Phase singularities, their tracking, the dominant frequency and the
// re-entry summary, on fields whose answers are known in closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "measure/cell_triangles.hpp"
#include "measure/dominant_frequency.hpp"
#include "measure/phase_singularities.hpp"
#include "measure/reentry.hpp"
#include "measure/singularity_tracking.hpp"
#include "report/run_report.hpp"
#include "report/singularity_panel.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kSpacing_um = 100;  // between neighbouring cells of the test grids

// An n x n square grid of cells kSpacing_um apart, joined to their 4
// neighbours (no triangles in the graph itself: the 4-cycles are split), or
// with one diagonal too (every square already two triangles).
Tissue grid(int n, bool diagonals) {
  Tissue t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) t.add_cell(CellType::myocyte, i * kSpacing_um, j * kSpacing_um);
  auto at = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) t.cell_edges.emplace_back(at(i, j), at(i + 1, j));
      if (j + 1 < n) t.cell_edges.emplace_back(at(i, j), at(i, j + 1));
      if (diagonals && i + 1 < n && j + 1 < n) t.cell_edges.emplace_back(at(i, j), at(i + 1, j + 1));
    }
  t.finalise();
  return t;
}

std::vector<double> field(const Tissue& t, const std::function<double(double x_um, double y_um)>& phase) {
  std::vector<double> p(t.cell_count());
  for (std::size_t c = 0; c < p.size(); ++c) p[c] = wrap_phase(phase(t.x_um[c], t.y_um[c]));
  return p;
}
}  // namespace

TEST_CASE("the triangles of a grid cover it once, counter-clockwise") {
  // An n x n grid has 2 (n-1)^2 triangles whether its squares are split by
  // their graph (4-neighbours) or by a diagonal edge; each of area h^2 / 2.
  for (bool diagonals : {false, true}) {
    const Tissue t = grid(6, diagonals);
    const auto triangles = cell_triangles(t);
    CHECK(triangles.size() == 2 * 5 * 5);
    for (const auto& tri : triangles) {
      const double area = 0.5 * ((t.x_um[tri[1]] - t.x_um[tri[0]]) * (t.y_um[tri[2]] - t.y_um[tri[0]]) -
                                 (t.x_um[tri[2]] - t.x_um[tri[0]]) * (t.y_um[tri[1]] - t.y_um[tri[0]]));
      CHECK(area == doctest::Approx(kSpacing_um * kSpacing_um / 2));
    }
  }
}

TEST_CASE("a rotating spiral has one phase singularity, at its centre within a cell") {
  // phase = atan2(y - y0, x - x0) - omega t increases by 2 pi counter-clockwise
  // around (x0, y0): charge +1 there, 0 in every other triangle.
  const double x0 = 1033, y0 = 987, omega = 2 * kPi / 200;
  for (bool diagonals : {false, true}) {
    const Tissue t = grid(21, diagonals);
    const auto triangles = cell_triangles(t);
    for (double time_ms : {0.0, 37.0, 120.0}) {
      CAPTURE(time_ms);
      const auto ps = find_phase_singularities(
          t, triangles, field(t, [&](double x, double y) { return std::atan2(y - y0, x - x0) - omega * time_ms; }));
      REQUIRE(ps.size() == 1);
      CHECK(ps[0].chirality == 1);
      CHECK(std::abs(ps[0].x_mm * 1000 - x0) <= kSpacing_um);
      CHECK(std::abs(ps[0].y_mm * 1000 - y0) <= kSpacing_um);
    }
  }
}

TEST_CASE("a planar wave has no phase singularity") {
  // Wavelength 1 mm over 0.1 mm cells: neighbours differ by 0.2 pi, well inside (-pi, pi].
  const Tissue t = grid(21, false);
  const double k = 2 * kPi / 1000;
  const auto ps = find_phase_singularities(t, cell_triangles(t),
                                           field(t, [&](double x, double y) { return k * (0.6 * x + 0.8 * y) - 1.3; }));
  CHECK(ps.empty());
}

TEST_CASE("two counter-rotating spirals have charges +1 and -1 at their centres") {
  const double x1 = 543, y1 = 1011, x2 = 1461, y2 = 989;
  const Tissue t = grid(21, false);
  const auto ps = find_phase_singularities(t, cell_triangles(t), field(t, [&](double x, double y) {
    return std::atan2(y - y1, x - x1) - std::atan2(y - y2, x - x2) - 0.4;
  }));
  REQUIRE(ps.size() == 2);
  for (const auto& p : ps) {
    const bool first = p.chirality == 1;
    CHECK(std::abs(p.x_mm * 1000 - (first ? x1 : x2)) <= kSpacing_um);
    CHECK(std::abs(p.y_mm * 1000 - (first ? y1 : y2)) <= kSpacing_um);
  }
  CHECK(ps[0].chirality + ps[1].chirality == 0);
}

TEST_CASE("phase singularities are linked frame to frame by the nearest of the same chirality") {
  SingularityTracker tracker(1.0);
  CHECK(tracker.add_frame(0, {{0.0, 0.0, 1}, {5.0, 0.0, -1}}) == std::vector<int>{0, 1});
  // Both move 0.4 mm; a new one appears next to id 0 but of the other chirality.
  CHECK(tracker.add_frame(1, {{5.4, 0.0, -1}, {0.4, 0.0, 1}, {0.5, 0.2, -1}}) == std::vector<int>{1, 0, 2});
  // id 0 jumps 2 mm (beyond link_mm): it dies, a new id is born; id 1 is gone.
  CHECK(tracker.add_frame(2, {{2.4, 0.0, 1}, {0.6, 0.2, -1}}) == std::vector<int>{3, 2});
  const auto& tracks = tracker.tracks();
  REQUIRE(tracks.size() == 4);
  CHECK(tracks[0].birth_ms == 0);
  CHECK(tracks[0].death_ms == 1);
  CHECK(tracks[0].trajectory.size() == 2);
  CHECK(tracks[1].death_ms == 1);
  CHECK(tracks[2].birth_ms == 1);
  CHECK(tracks[2].death_ms == 2);
  CHECK(tracks[3].birth_ms == 2);
  CHECK(tracker.max_per_frame() == 3);
}

TEST_CASE("the dominant frequency is the frequency of a sampled sine, on a bin") {
  // 7 Hz sampled every 2 ms for 2 s: bin 14 of resolution 0.5 Hz; a second
  // cell with a 3 Hz square-ish wave (its fundamental dominates); a third flat.
  const std::size_t cells = 3, samples = 1000;
  std::vector<float> frames(cells * samples);
  for (std::size_t m = 0; m < samples; ++m) {
    const double t_s = m * 0.002;
    frames[m * cells + 0] = static_cast<float>(-40 + 40 * std::sin(2 * kPi * 7 * t_s));
    frames[m * cells + 1] = std::sin(2 * kPi * 3 * t_s) > 0 ? 20.0f : -80.0f;
    frames[m * cells + 2] = -80.0f;
  }
  const auto df = dominant_frequencies(frames, cells, samples, 2.0, 1.0, 30.0);
  CHECK(df.resolution_hz == doctest::Approx(0.5));
  CHECK(df.per_cell_hz[0] == doctest::Approx(7.0));
  CHECK(df.per_cell_hz[1] == doctest::Approx(3.0));
  CHECK(std::isnan(df.per_cell_hz[2]));
}

TEST_CASE("re-entry from sampled V: a spiral's phase singularity, its frequency, and activity after the last stimulus") {
  // V = V* + 40 cos(omega t - theta), theta the angle about (x0, y0), period
  // 200 ms (5 Hz); tau a quarter period makes the embedding phase exactly
  // omega t - theta, which decreases counter-clockwise: one PS of charge -1.
  const Tissue t = grid(21, false);
  const double x0 = 1033, y0 = 987, period = 200, omega = 2 * kPi / period, V_star = -50;
  ReentrySettings s{.every_ms = 5, .from_ms = 0, .tau_ms = period / 4, .V_star_mV = V_star, .link_mm = 1};
  auto record = [&](double until_ms) {
    VoltageFrames frames(t.cell_count());
    for (double time = 0; time <= 1000 - 5 + 1e-9; time += 5) {
      std::vector<double> V(t.cell_count());
      for (std::size_t c = 0; c < V.size(); ++c)
        V[c] = time <= until_ms ? V_star + 40 * std::cos(omega * time - std::atan2(t.y_um[c] - y0, t.x_um[c] - x0))
                                : -80.0;
      frames.add(time, V);
    }
    return frames;
  };
  const auto dir = testing::scratch_dir("reentry_spiral");
  // Stimuli at 0 and 300 ms: cycle length 300 ms.
  const json r = analyse_reentry(t, record(1000), s, {0, 300}, {}, dir);
  CAPTURE(r.dump());
  CHECK(r["phase_singularities_max"] == 1);
  CHECK(r["phase_singularities_tracked"] == 1);
  // Seen from the first frame with a delayed sample (50 ms) to the last (995 ms).
  CHECK(r["longest_phase_singularity_ms"].get<double>() == doctest::Approx(945));
  // 200 samples over 1 s: resolution 1 Hz, the 5 Hz rotation on a bin.
  CHECK(r["dominant_frequency_hz"].get<double>() == doctest::Approx(5));
  CHECK(r["cycle_length_ms"].get<double>() == 300);
  CHECK(r["detected"] == true);
  // Upward crossings of V* at omega t - theta = -pi/2 (mod 2 pi): every cell
  // crosses once per 200 ms, so the last lies within one period of the record's end.
  CHECK(r["last_activation_ms"].get<double>() > 995 - period);
  CHECK(r["duration_ms"].get<double>() == doctest::Approx(r["last_activation_ms"].get<double>() - 300));

  const std::string csv = testing::read_file(dir / "phase_singularities.csv");
  CHECK(csv.rfind("t_ms,id,x_mm,y_mm,chirality\n", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 190);  // one PS in each frame from 50 to 995 ms
  CHECK(csv.find(",-1\n") != std::string::npos);

  // Activity that stops at 450 ms outlasts the last stimulus by less than a cycle: no re-entry.
  const json stopped = analyse_reentry(t, record(450), s, {0, 300}, {}, {});
  CHECK(stopped["detected"] == false);
  CHECK(stopped["duration_ms"].get<double>() <= 150);
  // With a single stimulus there is no cycle length to outlast.
  const json single = analyse_reentry(t, record(1000), s, {0}, {}, {});
  CHECK(single["cycle_length_ms"].is_null());
  CHECK(single["detected"] == false);
}

TEST_CASE("the fraction of myocytes a beat does not reach") {
  // Beat 0 fires all 4 myocytes; beat 1 leaves one unfired (as the tracker
  // writes a beat that did not fire: no activation, no APO; test_firing.cpp
  // checks the criterion). Fibroblasts do not count.
  std::vector<BeatBiomarkers> beats;
  for (int beat : {0, 1})
    for (int cell = 0; cell < 5; ++cell) {
      BeatBiomarkers b;
      b.cell = cell;
      b.beat = beat;
      b.type = cell == 4 ? CellType::fibroblast : CellType::myocyte;
      b.rmp_mV = -80;
      b.apo_mV = 20;
      b.activation_ms = 10.0 + cell;
      if ((beat == 1 && cell == 2) || cell == 4) b.activation_ms = b.apo_mV = std::nan("");
      beats.push_back(b);
    }
  const json f = unreached_fractions(beats);
  REQUIRE(f.size() == 2);
  CHECK(f[0]["fraction"] == 0.0);
  CHECK(f[1]["fraction"] == 0.25);
  CHECK(f[1]["myocytes"] == 4);
}

namespace {
// A 0.3 x 1 mm sheet of Colman myocytes paced from its bottom edge (a
// rectangle in mm) twice, period_ms apart, with output.reentry on.
struct PacedSheet {
  json summary;
  std::vector<BeatBiomarkers> beats;
};
PacedSheet paced_sheet(double period_ms, const std::filesystem::path& dir) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "paced_sheet", "seed": 1,
    "tissue": {"builder": "in_series", "width_mm": 0.3, "height_mm": 1.0, "fm_ratio": 0},
    "cells": {"myocyte": {"model": "colman"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2},
                  "start_ms": 10, "count": 2, "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"reentry": {"every_ms": 1, "tau_ms": 10}, "report": false}
  })");
  m["stimulus"][0]["period_ms"] = period_ms;
  m["duration_ms"] = period_ms + 100;
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  return {sim.summary(), sim.biomarkers()};
}
}  // namespace

TEST_CASE("a run with output.reentry: a planar wave has no phase singularity and no re-entry") {
  const auto dir = testing::scratch_dir("reentry_planar_sheet");
  const json s = paced_sheet(400, dir).summary;
  REQUIRE(s.contains("reentry"));
  const json& r = s["reentry"];
  CAPTURE(r.dump());
  CHECK(r["samples"] == 501);  // 0, 1, ..., 500 ms
  CHECK(r["phase_singularities_max"] == 0);
  CHECK(testing::read_file(dir / "phase_singularities.csv") == "t_ms,id,x_mm,y_mm,chirality\n");
  // Every cell activates once after the last stimulus (410 ms), the wave
  // crossing 1 mm within a few ms (CV well above 10 cm/s: < 10 ms).
  CHECK(r["activations_after_last_stimulus_max"] == 1);
  CHECK(r["last_activation_ms"].get<double>() > 410);
  CHECK(r["last_activation_ms"].get<double>() < 420);
  CHECK(r["cycle_length_ms"] == 400.0);
  CHECK(r["detected"] == false);
  // Both beats reach every myocyte; every cell's V spans the AP.
  REQUIRE(r["unreached_fraction_per_beat"].size() == 2);
  for (const auto& beat : r["unreached_fraction_per_beat"]) CHECK(beat["fraction"] == 0.0);
  CHECK(r["cells_in_spectrum"] == s["cells"]["myocyte"]);
  // Activation per beat: two beats (the two stimuli), each reaching every
  // myocyte; each cell's cycle length is the pacing interval, 400 ms, to
  // within one 1 ms sample (the second wave crosses the 1 mm sheet as fast
  // as the first within far less than that, both under 10 ms).
  REQUIRE(r["beats"].size() == 2);
  for (int b = 0; b < 2; ++b) {
    CHECK(r["beats"][b]["wave"] == 0);
    CHECK(r["beats"][b]["onset_ms"] == 10.0 + 400 * b);
    CHECK(r["beats"][b]["unreached_fraction"] == 0.0);
    CHECK(r["beats"][b]["counted"] == s["cells"]["myocyte"]);
  }
  CHECK(std::abs(r["activation_cycle_length_ms"].get<double>() - 400) <= 1.0);
  CHECK(r["cells_with_cycle_length"] == s["cells"]["myocyte"]);
  CHECK(r["beat_maps_drawn"] == 2);
  for (const char* file : {"activation_beat_000.png", "activation_beat_001.png", "dominant_frequency_map.png",
                           "clinical_dominant_frequency_map.png", "phase_singularity_density_map.png",
                           "phase_singularity_paths.png", "reentry_maps.vtk"})
    CHECK(std::filesystem::exists(dir / file));
  // No PS: no track, no rotor, no PS time; the density grid (1 mm bins over
  // the 0.3 x 1 mm sheet and its particles' edges: 1 x 2 bins) all zero.
  CHECK(r["longest_track"].is_null());
  CHECK(r["rotors"] == 0);
  CHECK(r["rotor_time_fraction"] == 0.0);
  CHECK(r["phase_singularity_seconds"] == 0.0);
  CHECK(testing::read_file(dir / "phase_singularity_tracks.csv").find('\n') + 1 ==
        testing::read_file(dir / "phase_singularity_tracks.csv").size());  // the header alone
  for (const auto& row : testing::csv_rows(dir / "phase_singularity_density.csv"))
    if (row[0] != "x_mm") CHECK(row[2] == "0");
  // The clinical band's peak lies in 3-12 Hz whatever the pacing (here 2.5 Hz).
  CHECK(r["clinical_band_hz"] == json::array({3.0, 12.0}));
  const double highest = r["highest_dominant_frequency"]["frequency_hz"].get<double>();
  CHECK(highest >= 3.0);
  CHECK(highest <= 12.0);
  // report.html shows the section, the maps, and says that there is no PS to draw.
  const std::string page = testing::read_file(write_run_report(dir));
  CHECK(page.find("Re-entry") != std::string::npos);
  CHECK(page.find("No phase singularity in phase_singularities.csv.") != std::string::npos);
  CHECK(page.find("<figcaption>Dominant frequency per cell (Hz)</figcaption><img") != std::string::npos);
  CHECK(page.find("Activation map per beat") != std::string::npos);
  CHECK(page.find("<img alt=\"beat 1, 0 not reached\"") != std::string::npos);
}

TEST_CASE("a run with output.reentry: a beat given to a region of uncoupled cells reaches that region alone") {
  // Without gap junctions (D_m_nS 0) a wave cannot spread: the first pulse,
  // over the whole sheet, excites every myocyte; the second, 400 ms later
  // (recovered), only those whose centre lies at y <= 0.2 mm. The expected
  // unreached fraction of beat 1 is counted from the tissue's own cell
  // coordinates, independently of the measure.
  const auto dir = testing::scratch_dir("reentry_uncoupled_region");
  json m = json::parse(R"({
    "fibrodem": 1, "name": "uncoupled", "seed": 1, "duration_ms": 500,
    "tissue": {"builder": "in_series", "width_mm": 0.3, "height_mm": 1.0, "fm_ratio": 0},
    "cells": {"myocyte": {"model": "colman"}},
    "coupling": {"D_m_nS": 0},
    "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000},
                 {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 0.2},
                  "start_ms": 410, "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"reentry": {"every_ms": 1, "tau_ms": 10}, "report": false}
  })");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  const Tissue& tissue = sim.tissue();
  std::size_t myocytes = 0, in_region = 0;
  for (std::size_t c = 0; c < tissue.cell_count(); ++c) {
    if (tissue.type[c] != CellType::myocyte) continue;
    ++myocytes;
    in_region += tissue.y_um[c] <= 200.0;
  }
  REQUIRE(in_region > 0);
  REQUIRE(in_region < myocytes);
  const json r = sim.summary()["reentry"];
  CAPTURE(r["beats"].dump());
  REQUIRE(r["beats"].size() == 2);
  CHECK(r["beats"][0]["unreached_fraction"] == 0.0);
  CHECK(r["beats"][1]["reached"] == in_region);
  CHECK(r["beats"][1]["unreached_fraction"].get<double>() ==
        doctest::Approx(1.0 - static_cast<double>(in_region) / myocytes).epsilon(1e-12));
}

TEST_CASE("a run with output.reentry: a beat inside the refractory period is blocked") {
  // The second pulse comes 200 ms after the first, before the first beat has
  // repolarised to its 90 % level (checked on the run's own biomarkers: the
  // first beat closes at the second onset with no APD90): the wave it starts
  // cannot cross the still refractory sheet.
  const PacedSheet sheet = paced_sheet(200, testing::scratch_dir("reentry_blocked_sheet"));
  for (const auto& b : sheet.beats)
    if (b.beat == 0) CHECK(std::isnan(b.apd90_ms));
  const json& fractions = sheet.summary["reentry"]["unreached_fraction_per_beat"];
  REQUIRE(fractions.size() == 2);
  CHECK(fractions[0]["fraction"] == 0.0);
  CHECK(fractions[1]["fraction"].get<double>() > 0.25);
}

TEST_CASE("the report draws each tracked phase singularity's trajectory, longest-lived first") {
  CsvTable table;
  table.header = {"t_ms", "id", "x_mm", "y_mm", "chirality"};
  table.rows = {{"1", "0", "0.5", "0.5", "1"},  {"1", "1", "2", "2", "-1"}, {"2", "0", "0.6", "0.5", "1"},
                {"3", "0", "0.7", "0.55", "1"}, {"3", "2", "3", "1", "1"},  {"4", "2", "3.1", "1", "1"}};
  const auto panel = singularity_trajectories(table);
  REQUIRE(panel);
  CHECK(panel->title == "Phase singularity trajectories (3 tracked)");
  REQUIRE(panel->series.size() == 3);
  // id 0 lives 2 ms, id 2 1 ms, id 1 a single frame.
  CHECK(panel->series[0].label == "PS 0 (+1)");
  CHECK(panel->series[0].x == std::vector<double>{0.5, 0.6, 0.7});
  CHECK(panel->series[0].y == std::vector<double>{0.5, 0.5, 0.55});
  CHECK(panel->series[1].label == "PS 2 (+1)");
  CHECK(panel->series[2].label == "PS 1 (-1)");
  table.rows.clear();
  CHECK_FALSE(singularity_trajectories(table));
}

namespace {
// A cross-field S1-S2 on a 2 x 5 mm sheet (3360 Colman myocytes) whose
// wavelength fits in it: conductance scales of the kind used for chronic AF
// remodelling (APD90 about 135 ms) and weak coupling (D_m 10 nS, about
// 2.6 cm/s along the fibres). S1 a plane wave from the bottom edge; S2 on
// the bottom-left quadrant 190 ms later, when the quadrant's lower part
// has recovered and the S1 wave's tail still lies above it.
json cross_field(bool with_s2, double duration_ms) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "cross_field", "seed": 1,
    "tissue": {"builder": "in_series", "width_mm": 2.0, "height_mm": 5.0, "fm_ratio": 0},
    "cells": {"myocyte": {"model": "colman", "parameters": {"g_CaL_scale": 0.35, "g_to_scale": 0.35,
              "g_Kur_scale": 0.5, "g_K1_scale": 2.0, "g_Ks_scale": 2.0}}},
    "coupling": {"D_m_nS": 10},
    "stimulus": [
      {"target": {"x_min_mm": -1, "x_max_mm": 3, "y_min_mm": -1, "y_max_mm": 0.2}, "start_ms": 10,
       "duration_ms": 2, "amplitude_pA": 4000},
      {"target": {"x_min_mm": -1, "x_max_mm": 1, "y_min_mm": -1, "y_max_mm": 2.5}, "start_ms": 200,
       "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02, "threads": 1},
    "output": {"reentry": {"every_ms": 2, "tau_ms": 10}, "report": false}
  })");
  if (!with_s2) m["stimulus"].erase(1);
  m["duration_ms"] = duration_ms;
  Simulation sim(parse_scene(m));
  sim.run();
  return sim.summary()["reentry"];
}
}  // namespace

TEST_CASE("a cross-field S1-S2 makes re-entry, S1 alone does not" * doctest::test_suite("slow")) {
  // Re-entry, independently of the phase: cells excited again after the
  // last stimulus with no stimulus to excite them (a plane wave excites
  // each cell once), and activity to the end of the run.
  const json r = cross_field(true, 600);
  CAPTURE(r.dump());
  CHECK(r["activations_after_last_stimulus_max"].get<int>() >= 2);
  CHECK(r["last_activation_ms"].get<double>() > 600 - r["cycle_length_ms"].get<double>());
  CHECK(r["detected"] == true);
  CHECK(r["phase_singularities_max"].get<int>() >= 1);
  CHECK(r["longest_phase_singularity_ms"].get<double>() >= 50);
  // The S1 wave alone crosses the sheet once (5 mm at about 2.6 cm/s: by
  // about 200 ms) and dies out at its far edge: one activation per cell, no
  // phase singularity.
  const json s1 = cross_field(false, 260);
  CAPTURE(s1.dump());
  CHECK(s1["activations_after_last_stimulus_max"] == 1);
  CHECK(s1["phase_singularities_max"] == 0);
  CHECK(s1["detected"] == false);
}

TEST_CASE("a wave anchored on a collagen region is one rotor, at the region's centre" * doctest::test_suite("slow")) {
  // examples/arrhythmia/cross_field.json's sheet and S1-S2 (3 x 6 mm,
  // colman2013_caf, D_m 10 nS) with a compact collagen region (no cells)
  // of 0.06 x 18 mm^2, 0.6 x 1.8 mm, its left edge on S2's right edge
  // (x = 1.5 mm), centred at (1.8, 1.5) mm: S2's free end catches on it and
  // turns around it. Its phase singularity is in the region, found by the
  // phase's winding around the region's rim (measure/cell_holes.hpp), and
  // stays at the rim's centroid: one track that is a rotor (a turn or
  // more), its mean position the region's centre within a cell (125 um
  // along the fibres, y), meander 0. (Searched on triangles of cells alone,
  // without its holes, the same run has 2 tracks, the longest 8 ms: no rotor.)
  const json m = json::parse(R"({
    "fibrodem": 1, "name": "anchored", "seed": 1, "duration_ms": 600,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 3, "length_mm": 6,
               "fibrosis": {"pattern": "compact", "as": "collagen", "density": 0.06, "aspect": 3,
                            "centre_x_frac": 0.6, "centre_y_frac": 0.25}},
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013_caf"}},
    "coupling": {"D_m_nS": 10},
    "stimulus": [
      {"target": {"x_min_mm": 0, "x_max_mm": 3, "y_min_mm": 0, "y_max_mm": 0.2, "type": "myocyte"},
       "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000},
      {"target": {"x_min_mm": 0, "x_max_mm": 1.5, "y_min_mm": 0, "y_max_mm": 3, "type": "myocyte"},
       "start_ms": 200, "duration_ms": 2, "amplitude_pA": 4000}],
    "solver": {"method": "auto", "threads": 1},
    "output": {"reentry": {"every_ms": 2, "tau_ms": 10}, "report": false}
  })");
  Simulation sim(parse_scene(m));
  sim.run();
  const json r = sim.summary()["reentry"];
  CAPTURE(r.dump());
  CHECK(r["detected"] == true);
  CHECK(r["rotors"] == 1);
  const json& track = r["longest_track"];
  REQUIRE(track.is_object());
  CHECK(track["rotor"] == true);
  CHECK(track["rotations"].get<double>() >= 1);
  CHECK(std::abs(track["x_mm"].get<double>() - 1.8) < 0.125);
  CHECK(std::abs(track["y_mm"].get<double>() - 1.5) < 0.125);
  CHECK(track["meander_extent_mm"] == 0.0);
}

TEST_CASE("re-entry frames: room made for the samples to come holds them without moving") {
  // A run reserves every frame when its sampling starts, so that the array
  // never doubles (both copies resident while it moves) during the run.
  VoltageFrames frames(5);
  frames.add(0.0, std::vector<double>(5, -80.0));
  frames.reserve_more(3);
  const float* first = frames.frame(0);
  for (int k = 1; k <= 3; ++k) frames.add(k, std::vector<double>(5, -80.0 + k));
  CHECK(frames.count() == 4);
  CHECK(frames.frame(0) == first);  // not moved
  CHECK(frames.values.capacity() == 20);
  CHECK(frames.frame(3)[4] == doctest::Approx(-77.0));
}
