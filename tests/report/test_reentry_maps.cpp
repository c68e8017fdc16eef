// Activation per beat, block per beat and cycle length on sampled V whose
// activations are set by construction; the frames of report.html's snapshot
// animation; the vulnerable-window search's report page; the bound on the
// maps a long run writes.
#include <doctest/doctest.h>

#include <cairo.h>

#include <cmath>
#include <cstdint>
#include <fstream>

#include "measure/beat_activations.hpp"
#include "measure/reentry.hpp"
#include "report/run_report.hpp"
#include "report/snapshot_frames.hpp"
#include "report/vulnerable_window_report.hpp"
#include "run/reentry_maps.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// V of `cells` cells sampled every 1 ms from 0 to end_ms: at rest (-80 mV)
// except +20 mV from each of its activation times for 100 ms (a square
// action potential), so each activation is one upward crossing of -50 mV,
// found by interpolation 0.3 ms after the sample before it.
VoltageFrames square_waves(const std::vector<std::vector<double>>& activations, double end_ms) {
  VoltageFrames frames(activations.size());
  for (double t = 0; t <= end_ms; t += 1) {
    std::vector<double> V(activations.size(), -80.0);
    for (std::size_t c = 0; c < activations.size(); ++c)
      for (double a : activations[c])
        if (t >= a && t < a + 100) V[c] = 20.0;
    frames.add(t, V);
  }
  return frames;
}

// The crossing the interpolation finds for an activation at a (not on a
// sample): the sample before it + (-50 - -80) / (20 - -80) ms.
double interpolated(double a) { return std::ceil(a) - 1 + 0.3; }

// A row of 20 cells, a planar wave from cell 0 at each onset, 0.35 ms per
// cell (offsets not on the 1 ms samples).
constexpr std::size_t kRow = 20;
double arrival(double onset_ms, std::size_t cell) { return onset_ms + 0.5 + 0.35 * cell; }

}  // namespace

TEST_CASE("a planar wave paced twice: two beats, none blocked, cycle length the pacing interval") {
  const std::vector<double> onsets = {10, 310};
  std::vector<std::vector<double>> set(kRow);
  for (std::size_t c = 0; c < kRow; ++c)
    for (double onset : onsets) set[c].push_back(arrival(onset, c));
  const VoltageFrames frames = square_waves(set, 600);
  const auto found = activation_times(frames, -50);
  for (std::size_t c = 0; c < kRow; ++c) {
    REQUIRE(found[c].size() == 2);
    for (int k = 0; k < 2; ++k) CHECK(found[c][k] == doctest::Approx(interpolated(set[c][k])).epsilon(1e-12));
  }
  const BeatActivations beats = assign_beats(found, onsets, std::vector<bool>(kRow, true));
  REQUIRE(beats.beats.size() == 2);
  for (int b = 0; b < 2; ++b) {
    const BeatMap& beat = beats.beats[b];
    CHECK(beat.beat == b);
    CHECK(beat.wave == 0);
    CHECK(*beat.onset_ms == onsets[b]);
    CHECK(beat.unreached_fraction() == 0.0);
    // Each cell's time in the map is its constructed arrival, to within one 1 ms sample.
    for (std::size_t c = 0; c < kRow; ++c) CHECK(std::abs(beat.activation_ms[c] - arrival(onsets[b], c)) < 1.0);
  }
  // The onsets are 300 ms apart, a whole number of samples: each cell's two
  // crossings lie at the same offset from their samples, 300 ms apart.
  const json s = beats_summary(beats);
  CHECK(s["activation_cycle_length_ms"].get<double>() == doctest::Approx(300).epsilon(1e-12));
  CHECK(s["cells_with_cycle_length"] == kRow);
  CHECK(s["beats"][1]["first_activation_ms"].get<double>() == doctest::Approx(interpolated(arrival(310, 0))));
  CHECK(s["beats"][1]["last_activation_ms"].get<double>() == doctest::Approx(interpolated(arrival(310, kRow - 1))));
}

TEST_CASE("V hovering about V* is one activation, a fall 10 mV below V* re-arms the cell") {
  // Cell 0 crosses -50 mV five times in one excitation (-52, -48, -51, -47,
  // ..., never below -60 mV between): one activation. Cell 1 does the same
  // but falls to -61 mV between its second and third crossings: two.
  VoltageFrames frames(2);
  const std::vector<double> hover = {-80, -52, -48, -51, -47, -51, -46, -52, -45, -80, -80};
  const std::vector<double> rearmed = {-80, -52, -48, -61, -47, -51, -46, -52, -45, -80, -80};
  for (std::size_t k = 0; k < hover.size(); ++k) frames.add(static_cast<double>(k), {hover[k], rearmed[k]});
  const auto found = activation_times(frames, -50);
  REQUIRE(found[0].size() == 1);
  CHECK(found[0][0] == doctest::Approx(1.5));  // -52 at 1 ms, -48 at 2 ms
  REQUIRE(found[1].size() == 2);
  CHECK(found[1][1] == doctest::Approx(3 + 11.0 / 14));  // -61 at 3 ms, -47 at 4 ms
}

TEST_CASE("a beat blocked beyond a line leaves the cells past it unreached, fibroblasts not counted") {
  // The second wave stops before cell 15: 5 of the 20 myocytes (0.25) are
  // not reached. Four fibroblasts (never activated) are not counted.
  const std::vector<double> onsets = {10, 310};
  std::vector<std::vector<double>> set(kRow + 4);
  std::vector<bool> myocyte(kRow + 4, false);
  for (std::size_t c = 0; c < kRow; ++c) {
    myocyte[c] = true;
    set[c].push_back(arrival(10, c));
    if (c < 15) set[c].push_back(arrival(310, c));
  }
  const BeatActivations beats = assign_beats(activation_times(square_waves(set, 600), -50), onsets, myocyte);
  REQUIRE(beats.beats.size() == 2);
  CHECK(beats.beats[0].unreached_fraction() == 0.0);
  CHECK(beats.beats[1].counted == kRow);
  CHECK(beats.beats[1].reached == 15);
  CHECK(beats.beats[1].unreached_fraction() == 0.25);
  CHECK(std::isnan(beats.beats[1].activation_ms[17]));
  const json s = beats_summary(beats);
  CHECK(s["cells_with_cycle_length"] == 15);  // one activation only: no interval
}

TEST_CASE("activations after the last stimulus without one are later waves of its beat") {
  // One stimulus at 10 ms; cells 0-9 are re-excited 200 ms after their first
  // activation (a re-entrant wave), cells 10-19 are not: beat 1 is the
  // window's wave 1, reaching half of the cells; those cells' cycle length
  // is 200 ms.
  std::vector<std::vector<double>> set(kRow);
  for (std::size_t c = 0; c < kRow; ++c) {
    set[c].push_back(arrival(10, c));
    if (c < 10) set[c].push_back(arrival(210, c));
  }
  const BeatActivations beats = assign_beats(activation_times(square_waves(set, 600), -50), {10}, std::vector<bool>(kRow, true));
  REQUIRE(beats.beats.size() == 2);
  CHECK(beats.beats[1].wave == 1);
  CHECK(*beats.beats[1].onset_ms == 10);
  CHECK(beats.beats[1].unreached_fraction() == 0.5);
  CHECK(beats_summary(beats)["activation_cycle_length_ms"].get<double>() == doctest::Approx(200).epsilon(1e-12));
}

TEST_CASE("the animation's frames: at most 60, spread evenly with both ends, scaled to the page's width") {
  const auto picked = evenly_spread(101, 60);
  REQUIRE(picked.size() == 60);
  CHECK(picked.front() == 0);
  CHECK(picked.back() == 100);
  for (std::size_t k = 1; k < picked.size(); ++k) CHECK(picked[k] > picked[k - 1]);
  CHECK(evenly_spread(5, 60).size() == 5);

  // A folder of 101 snapshots 1600 x 1000 px (plain grey), as a run leaves them.
  const auto dir = testing::scratch_dir("reentry_maps_animation");
  cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1600, 1000);
  cairo_t* cr = cairo_create(image);
  cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
  cairo_paint(cr);
  cairo_destroy(cr);
  for (int t = 0; t <= 100; ++t) {
    char name[64];
    std::snprintf(name, sizeof name, "snapshot_%09.3f_ms.png", static_cast<double>(t));
    REQUIRE(cairo_surface_write_to_png(image, (dir / name).c_str()) == CAIRO_STATUS_SUCCESS);
  }
  cairo_surface_destroy(image);
  // Width and height from the PNG's IHDR chunk (bytes 16-23, big-endian).
  const std::string small = png_at_most_wide(dir / "snapshot_00000.000_ms.png", kAnimationWidthPx);
  REQUIRE(small.size() > 24);
  auto be32 = [&](std::size_t at) {
    return (unsigned(static_cast<unsigned char>(small[at])) << 24) | (unsigned(static_cast<unsigned char>(small[at + 1])) << 16) |
           (unsigned(static_cast<unsigned char>(small[at + 2])) << 8) | unsigned(static_cast<unsigned char>(small[at + 3]));
  };
  CHECK(be32(16) == 720u);
  CHECK(be32(20) == 450u);  // 1000 x 720 / 1600

  const std::string page = testing::read_file(write_run_report(dir));
  CHECK(occurrences(page, "<img alt=\"t = ") == 60);
  CHECK(page.find("Membrane potential (60 of 101 snapshots)") != std::string::npos);
  CHECK(page.find("<img alt=\"t = 0.000 ms\"") != std::string::npos);
  CHECK(page.find("<img alt=\"t = 100.000 ms\"") != std::string::npos);
  CHECK(occurrences(page, "onclick=\"fibrodemPlay(") == 1);
  CHECK(page.find("function fibrodemPlay(") != std::string::npos);
}

TEST_CASE("the vulnerable-window report shows the bisected window and every interval, induced or not") {
  // A folder as run_vulnerable_window leaves it: four scanned intervals, two
  // of the bisection, one window [164, 219] ms.
  const auto dir = testing::scratch_dir("reentry_maps_window_report");
  std::ofstream(dir / "vulnerable_window.json") << R"({"scan": {"from_ms": 140, "to_ms": 240, "step_ms": 40,
    "resolution_ms": 1}, "s1_last_onset_ms": 10, "capture_fraction": 0.5, "runs": 5, "failed": 0,
    "overall": [{"lower_ms": 164, "upper_ms": 219, "open_below": false, "open_above": false}],
    "per_seed": [{"seed": 1, "windows": [{"lower_ms": 164, "upper_ms": 219, "open_below": false, "open_above": false}]}]})";
  std::ofstream(dir / "vulnerable_window.csv") << "interval_ms,seed,outcome,duration_ms,ps_max,stage,run\n"
                                                  "140,1,no_capture,0,0,scan,runs/ci_140ms_seed_1\n"
                                                  "163,1,no_capture,0,0,bisection,runs/ci_163ms_seed_1\n"
                                                  "164,1,reentry,300,4,bisection,runs/ci_164ms_seed_1\n"
                                                  "180,1,reentry,300,5,scan,runs/ci_180ms_seed_1\n"
                                                  "220,1,no_reentry,190,0,scan,runs/ci_220ms_seed_1\n";
  // Two runs' folders: one with its report, one with its summary only; the
  // other three are missing (no link).
  std::filesystem::create_directories(dir / "runs" / "ci_164ms_seed_1");
  std::filesystem::create_directories(dir / "runs" / "ci_180ms_seed_1");
  std::ofstream(dir / "runs" / "ci_164ms_seed_1" / "report.html") << "<html></html>";
  std::ofstream(dir / "runs" / "ci_180ms_seed_1" / "summary.json") << "{}";
  CHECK(is_vulnerable_window_folder(dir));
  const std::string page = testing::read_file(write_vulnerable_window_report(dir));
  CHECK(page.find("<li>[164, 219] ms</li>") != std::string::npos);
  CHECK(page.find("<th>induced</th>") != std::string::npos);
  // One "yes" per re-entry row, one "no" per other row (the table's cells).
  CHECK(occurrences(page, "<td>yes</td>") == 2);
  CHECK(occurrences(page, "<td>no</td>") == 3);
  CHECK(occurrences(page, "<a href=\"runs/ci_") == 2);
  CHECK(page.find("<a href=\"runs/ci_164ms_seed_1/report.html\">") != std::string::npos);
  CHECK(page.find("<a href=\"runs/ci_180ms_seed_1/summary.json\">") != std::string::npos);
  CHECK(!is_vulnerable_window_folder(dir / "nowhere"));
  CHECK_THROWS_WITH_AS(write_vulnerable_window_report(dir / "nowhere"),
                       doctest::Contains("vulnerable_window.json"), std::runtime_error);
}

TEST_CASE("a long run's maps stay bounded: the first 24 beats drawn, every beat in the VTK file's fields drawn") {
  // 30 beats on 2 x 2 cells: 24 pictures (kMostBeatMaps), the 25th not;
  // the VTK file holds the dominant frequency, the cycle length and the 24
  // beats' activation times (26 fields).
  Tissue tissue;
  for (int c = 0; c < 4; ++c) tissue.add_cell(CellType::myocyte, 100.0 * (c % 2), 100.0 * (c / 2));
  tissue.finalise();
  ReentryMaps maps;
  maps.dominant_frequency_hz = {5, 5, 6, 6};
  maps.beats.cycle_length_ms = {200, 200, 200, 200};
  for (int b = 0; b < 30; ++b) {
    BeatMap beat;
    beat.beat = b;
    beat.onset_ms = 10.0;
    beat.wave = b;
    beat.activation_ms = {float(200 * b), float(200 * b + 1), float(200 * b + 2), float(200 * b + 3)};
    beat.counted = beat.reached = 4;
    maps.beats.beats.push_back(beat);
  }
  const auto dir = testing::scratch_dir("reentry_maps_bounded");
  CHECK(write_reentry_maps(dir, "row", tissue, maps, "legacy") == kMostBeatMaps);
  CHECK(kMostBeatMaps == 24);
  CHECK(std::filesystem::exists(dir / "dominant_frequency_map.png"));
  CHECK(std::filesystem::exists(dir / beat_map_name(23)));
  CHECK(!std::filesystem::exists(dir / beat_map_name(24)));
  CHECK(beat_map_name(7) == "activation_beat_007.png");
  const std::string vtk = testing::read_file(dir / "reentry_maps.vtk");
  CHECK(occurrences(vtk, "activation_beat_") == 24);
  CHECK(vtk.find("activation_beat_23_ms") != std::string::npos);
  CHECK(vtk.find("dominant_frequency_hz") != std::string::npos);
  CHECK(vtk.find("cycle_length_ms") != std::string::npos);
}

namespace {
// The pixels of a PNG file that are red (a chirality -1 tip path's colour:
// no colour of the map's scale, white, black or grey is).
std::size_t red_pixels(const std::filesystem::path& png) {
  cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
  REQUIRE(cairo_surface_status(image) == CAIRO_STATUS_SUCCESS);
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  std::size_t red = 0;
  for (int y = 0; y < cairo_image_surface_get_height(image); ++y)
    for (int x = 0; x < cairo_image_surface_get_width(image); ++x) {
      const auto pixel = *reinterpret_cast<const std::uint32_t*>(data + y * stride + 4 * x);
      const unsigned r = (pixel >> 16) & 0xff, g = (pixel >> 8) & 0xff, b = pixel & 0xff;
      red += r > 200 && g < 60 && b < 60;
    }
  cairo_surface_destroy(image);
  return red;
}
}  // namespace

TEST_CASE("the tip paths are drawn over the map given, red for chirality -1") {
  // A 10 x 10 sheet of disks 0.1 mm apart coloured by any per-cell field
  // (here a ramp, as a strain map would be), a path across its middle.
  Tissue tissue;
  for (int c = 0; c < 100; ++c) {
    const int cell = tissue.add_cell(CellType::myocyte, 100.0 * (c % 10), 100.0 * (c / 10));
    tissue.add_particle(cell, 100.0 * (c % 10), 100.0 * (c / 10), 50);
  }
  tissue.finalise();
  MapField ramp{{}, "strain", "a ramp"};
  for (int c = 0; c < 100; ++c) ramp.values.push_back(c / 100.0);
  SingularityTrack track;
  track.trajectory = {{0, 0.2, 0.2}, {1, 0.5, 0.4}, {2, 0.7, 0.7}};
  track.death_ms = 2;
  const auto dir = testing::scratch_dir("tip_path_map");
  for (int chirality : {-1, 1}) {
    track.chirality = chirality;
    write_tip_path_map(dir / "paths.png", "sheet", tissue, {track}, ramp);
    CAPTURE(chirality);
    if (chirality < 0) CHECK(red_pixels(dir / "paths.png") > 50);
    else CHECK(red_pixels(dir / "paths.png") == 0);  // white
  }
  write_tip_path_map(dir / "none.png", "sheet", tissue, {}, ramp);
  CHECK(red_pixels(dir / "none.png") == 0);
}
