// Stimulus pulses: on/off times, edges, and CVODE never stepping over a pulse.
#include <doctest/doctest.h>

#include <cmath>

#include "stimulus/stimulus.hpp"
#include "support/scenes.hpp"
#include "tissue/cell_partition.hpp"
#include "tissue/tissue_builder.hpp"

using namespace fibrodem;

TEST_CASE("a periodic pulse train is on exactly in its pulses") {
  PulseTrain train{{0}, 50.0, 2.0, 2000.0, 1000.0, 3, {0}};
  CHECK_FALSE(train.on(49.999));
  CHECK(train.on(50.0));
  CHECK(train.on(51.999));
  CHECK_FALSE(train.on(52.0));
  CHECK(train.on(1050.0));
  CHECK(train.on(2051.0));
  CHECK_FALSE(train.on(3050.5));  // count = 3
  // n * dt round-off: 5000 * 0.01 is not exactly 50.
  CHECK(train.on(5000 * 0.01));
  CHECK_FALSE(train.on(5200 * 0.01));
}

TEST_CASE("edges and onsets of the stimulus") {
  json m = testing::passive_cell_manifest();
  m["stimulus"] = json::array({{{"target", "fibroblast"}, {"start_ms", 50}, {"duration_ms", 2},
                                {"amplitude_pA", 5}, {"period_ms", 1000}}});
  Scene scene = parse_scene(m);
  Tissue tissue = scene.tissue->build(0);
  Stimulus stimulus(scene.stimuli, tissue);
  CHECK(stimulus.next_edge_after(0) == 50);
  CHECK(stimulus.next_edge_after(50) == 52);
  CHECK(stimulus.next_edge_after(52) == 1050);
  CHECK(stimulus.onsets(3000) == std::vector<double>{50, 1050, 2050});
  std::vector<double> i(1, 0.0);
  stimulus.add_current(51, i.data());
  CHECK(i[0] == 5);
}

TEST_CASE("CVODE does not step over a short pulse and delivers its exact charge") {
  // Passive cell, 2 ms x 10 pA at t = 500.3 ms after a long quiet spell in which
  // CVODE's step would grow far beyond 2 ms. Exact rise at the pulse end:
  // I R (1 - exp(-2 / RC)), RC = 10.7 GOhm x 6.3 pF.
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 600;
  m["stimulus"] = json::array({{{"target", "fibroblast"}, {"start_ms", 500.3}, {"duration_ms", 2},
                                {"amplitude_pA", 10}}});
  m["solver"] = {{"method", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-8}, {"max_step_ms", 1000}};
  m["output"]["traces"] = {{"cells", {0}}, {"variables", {"V"}}, {"every_ms", 0.1}};
  Simulation sim(parse_scene(m));
  sim.run();
  const auto& t = sim.trace_times();
  const auto& V = sim.trace("V", 0);
  const double rise = 10 * 10.7 * (1 - std::exp(-2 / (10.7 * 6.3)));
  for (std::size_t k = 0; k < t.size(); ++k)
    if (std::abs(t[k] - 502.3) < 1e-9) CHECK(V[k] - (-49.6) == doctest::Approx(rise).epsilon(1e-5));
  CHECK(*std::max_element(V.begin(), V.end()) == doctest::Approx(-49.6 + rise).epsilon(1e-5));
}

namespace {
// An in-series sheet of myocytes and fibroblasts, 1 x 2 mm, with a
// stimulus target to resolve on it.
struct Sheet {
  Tissue tissue;
  std::vector<int> cells;
};
Sheet resolve_on_sheet(const json& target) {
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "in_series"}, {"width_mm", 1.0}, {"height_mm", 2.0}, {"fm_ratio", 0.41}};
  m["cells"]["myocyte"] = {{"model", "colman"}};
  m["stimulus"][0]["target"] = target;
  Scene scene = parse_scene(m);
  Sheet sheet{scene.tissue->build(0), {}};
  Stimulus stimulus(scene.stimuli, sheet.tissue);
  sheet.cells = stimulus.trains()[0].cells;
  return sheet;
}
}  // namespace

TEST_CASE("a rectangle in mm takes exactly the cells whose centre lies in it") {
  // Reference: the cells counted directly from their centres, here.
  const json rect = {{"x_min_mm", 0.2}, {"x_max_mm", 0.6}, {"y_min_mm", 0.5}, {"y_max_mm", 1.1}};
  const Sheet sheet = resolve_on_sheet(rect);
  std::vector<int> expected;
  for (int c = 0; c < static_cast<int>(sheet.tissue.cell_count()); ++c) {
    const double x = sheet.tissue.x_um[c], y = sheet.tissue.y_um[c];
    if (x >= 200 && x <= 600 && y >= 500 && y <= 1100) expected.push_back(c);
  }
  REQUIRE(expected.size() > 10);
  CHECK(expected.size() < sheet.tissue.cell_count() / 2);
  CHECK(sheet.cells == expected);
  // With a type filter: the myocytes among them.
  json myocytes_only = rect;
  myocytes_only["type"] = "myocyte";
  std::vector<int> expected_myocytes;
  for (int c : expected)
    if (sheet.tissue.type[c] == CellType::myocyte) expected_myocytes.push_back(c);
  REQUIRE(expected_myocytes.size() < expected.size());  // the sheet has fibroblasts in it
  CHECK(resolve_on_sheet(myocytes_only).cells == expected_myocytes);
}

TEST_CASE("a circle in mm takes exactly the cells whose centre lies in it") {
  const Sheet sheet = resolve_on_sheet({{"center_x_mm", 0.5}, {"center_y_mm", 1.0}, {"radius_mm", 0.3}});
  std::vector<int> expected;
  for (int c = 0; c < static_cast<int>(sheet.tissue.cell_count()); ++c)
    if (std::hypot(sheet.tissue.x_um[c] - 500, sheet.tissue.y_um[c] - 1000) <= 300) expected.push_back(c);
  REQUIRE(expected.size() > 10);
  CHECK(sheet.cells == expected);
}

TEST_CASE("the fractions form of a region still selects by the bounding box") {
  const Sheet sheet = resolve_on_sheet({{"y_max_frac", 0.25}});
  const auto box = sheet.tissue.bounds_um();
  std::vector<int> expected;
  for (int c = 0; c < static_cast<int>(sheet.tissue.cell_count()); ++c)
    if ((sheet.tissue.y_um[c] - box[2]) / (box[3] - box[2]) <= 0.25) expected.push_back(c);
  REQUIRE(!expected.empty());
  CHECK(sheet.cells == expected);
}

TEST_CASE("a rank's stimulus goes into its own cells only, and is undone where it went") {
  // Two trains on a strand of 6 cells, overlapping at cell 2; a rank owning
  // the even cells, the odd ones its ghosts. It holds its cells as 0 2 4
  // then 1 3 5 (tissue/cell_numbering.hpp): tissue cells 0 and 2 are held
  // cells 0 and 1. Expected currents counted by hand from the amplitudes.
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "strand"}, {"cells", 6}, {"type", "fibroblast"}};
  m["stimulus"] = json::array({{{"target", {0, 1, 2}}, {"start_ms", 1}, {"duration_ms", 2}, {"amplitude_pA", 5}},
                               {{"target", {2, 3}}, {"start_ms", 2}, {"duration_ms", 2}, {"amplitude_pA", 7}}});
  Scene scene = parse_scene(m);
  Stimulus stimulus(scene.stimuli, scene.tissue->build(0));
  std::vector<double> i_ext(6, 0.0);
  stimulus.add_current(2.5, i_ext.data());
  CHECK(i_ext == std::vector<double>{5, 5, 12, 7, 0, 0});
  RankCells share;
  share.owned = {0, 2, 4};
  share.ghosts = {1, 3, 5};
  stimulus.hold_only(CellNumbering(6, share));
  CHECK(stimulus.trains()[1].cells == std::vector<int>{2, 3});  // (the stimulated cells, for the measures)
  std::vector<double> held(6, 9.0);
  stimulus.clear_current(held.data());
  CHECK(held == std::vector<double>{0, 0, 9, 9, 9, 9});  // the rank's own stimulated cells cleared, nothing else
  stimulus.add_current(2.5, held.data());
  CHECK(held == std::vector<double>{5, 12, 9, 9, 9, 9});
  stimulus.clear_current(held.data());
  CHECK(held == std::vector<double>{0, 0, 9, 9, 9, 9});
}

TEST_CASE("a rank holding part of the cells finds every target's cells, and every error, as the whole tissue does") {
  // The rank reads every cell's type and centre from the builder's stream
  // (Tissue::hold_cells_of): the cells it does not hold are stimulated in
  // the measures' list too, and a region holding no cell is the same
  // error on every rank. The reference is the stimulus resolved on the
  // whole tissue.
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "in_series"}, {"width_mm", 1.0}, {"height_mm", 2.0}, {"fm_ratio", 0.41}};
  m["cells"]["myocyte"] = {{"model", "colman"}};
  const json targets =
      json::array({{{"x_min_mm", 0.2}, {"x_max_mm", 0.6}, {"y_min_mm", 0.5}, {"y_max_mm", 1.1}, {"type", "myocyte"}},
                   {{"center_x_mm", 0.5}, {"center_y_mm", 1.0}, {"radius_mm", 0.3}},
                   {{"y_max_frac", 0.25}},
                   "fibroblast",
                   {{"x_min_mm", 5}, {"x_max_mm", 6}, {"y_min_mm", 0}, {"y_max_mm", 1}}});
  for (const auto& target : targets) {
    CAPTURE(target.dump());
    m["stimulus"][0]["target"] = target;
    const Scene scene = parse_scene(m);
    const Tissue whole = scene.tissue->build(0);
    std::shared_ptr<const CellStream> stream = scene.tissue->stream_cells(0);
    Tissue part = stream->cell_types();
    cut_without_graph(part, 3, 1, stream);
    REQUIRE(part.cells_partial());
    REQUIRE(part.held_cells().size() < whole.cell_count() / 2);
    std::string whole_error, part_error;
    std::vector<int> whole_cells, part_cells;
    try {
      whole_cells = Stimulus(scene.stimuli, whole).trains()[0].cells;
    } catch (const ManifestError& e) {
      whole_error = e.what();
    }
    try {
      part_cells = Stimulus(scene.stimuli, part).trains()[0].cells;
    } catch (const ManifestError& e) {
      part_error = e.what();
    }
    CHECK(part_cells == whole_cells);
    CHECK(part_error == whole_error);
    CHECK((whole_cells.empty() == !whole_error.empty()));  // (the last target lies off the tissue)
  }
}
