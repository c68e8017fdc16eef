// coupling.regions: a junction whose midpoint lies in a region takes the
// region's conductances (the last region wins). Known answers: a strip of a
// quarter of the conductance conducts as a strand of that conductance
// throughout; a region that changes nothing gives the same bits as none;
// the reader's and the coupler's errors name the region.
#include <doctest/doctest.h>

#include <cmath>
#include <iomanip>

#include "coupling/gap_junction.hpp"
#include "tissue/cell_partition.hpp"
#include "tissue/rank_cells.hpp"
#include "support/paced_strand.hpp"

using namespace fibrodem;

using testing::cv_between;
using testing::paced_strand;

TEST_CASE("a strip with a quarter of the conductance conducts as a strand of that conductance") {
  // 80 cells (10 mm); the strip covers 4-7 mm. CVs are fitted over the
  // middle of each stretch, away from the ends and the strip's edges.
  json m = paced_strand(80);
  m["coupling"]["regions"] = json::array({{{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {4, 7}}, {"scale", 0.25}}});
  Simulation with_strip(parse_scene(m));
  with_strip.run();
  const double outside = cv_between(with_strip, 1.5, 3.5), inside = cv_between(with_strip, 4.5, 6.5);
  // The same strand at 250 nS throughout, fitted over the same cells.
  json slow = paced_strand(80);
  slow["coupling"]["D_m_nS"] = 250;
  Simulation uniform(parse_scene(slow));
  uniform.run();
  const double uniform_250 = cv_between(uniform, 4.5, 6.5);
  MESSAGE(std::setprecision(6), "CV outside ", outside, " cm/s, in the strip ", inside, " cm/s (ratio ",
          inside / outside, "); a strand at 250 nS: ", uniform_250, " cm/s");
  // Inside the strip the wave runs as on a strand of the strip's conductance.
  CHECK(inside == doctest::Approx(uniform_250).epsilon(0.02));
  // Continuous tissue would give sqrt(0.25) = 0.5. The discrete strand is
  // slower than that at 250 nS: its cells are isopotential, so the front
  // crosses each junction with a delay that grows as g falls (Shaw & Rudy
  // 1997); measured 0.476. Within 0.40-0.50.
  CHECK(inside / outside < 0.5);
  CHECK(inside / outside > 0.40);
}

TEST_CASE("regions that change nothing give the same bits as none") {
  const auto run_traces = [](const json& m, const std::string& name) {
    json with_dir = m;
    const auto dir = testing::scratch_dir(name);
    with_dir["output"]["dir"] = dir.string();
    with_dir["output"]["traces"] = {{"cells", {0, 10, 20, 29}}, {"variables", {"V"}}, {"every_ms", 0.5}};
    Simulation sim(parse_scene(with_dir));
    sim.run();
    return testing::read_file(dir / "traces.csv");
  };
  const json plain = paced_strand(30);
  const std::string none = run_traces(plain, "regions_none");
  json m = plain;
  // scale 1 everywhere; then D_m_nS as the section's over part of it.
  m["coupling"]["regions"] = json::array({{{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {-1, 10}}, {"scale", 1}},
                                          {{"shape", "ellipse"}, {"x_mm", {-1, 1}}, {"y_mm", {1, 2}}, {"D_m_nS", 1000}}});
  CHECK(run_traces(m, "regions_same") == none);
  // A region wholly under a later one holds no junction: named.
  m["coupling"]["regions"] = json::array({{{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {1, 2}}, {"scale", 0.1}},
                                          {{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {-1, 10}}, {"scale", 1}}});
  CHECK_THROWS_WITH_AS(run_traces(m, "regions_hidden"),
                       doctest::Contains("coupling.regions[0]: holds no junction"), ManifestError);
}

TEST_CASE("a region's conductances: scale times the section's, or its own, D_m_side_nS following its D_m_nS") {
  // Two columns of 8 cells (0.05 x 1 mm): junction midpoints end to end at
  // x = 0 or 23.57 um, side to side at 11.8 um.
  const Tissue t = testing::build_tissue({{"builder", "fibrotic_sheet"}, {"width_mm", 0.05}, {"length_mm", 1}}, 1);
  const std::vector<double> C(t.cell_count(), 50.0);
  const JunctionConductances base{1000, 400, 2};
  const auto total_of_cell_0 = [&](const json& regions) {
    const auto read = read_coupling_regions(regions, "coupling.regions", base);
    return GapJunctionCoupler(t, base, C, read).total_conductance_nS()[0];
  };
  // Cell 0: one end-to-end junction (to cell 1) and one side to side.
  int ends = 0, sides = 0;
  for (const auto& [i, j] : t.cell_edges)
    if (i == 0) end_to_end(t, i, j) ? ++ends : ++sides;
  REQUIRE(ends == 1);
  REQUIRE(sides == 1);
  const json everywhere = {{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {-1, 2}}};
  CHECK(total_of_cell_0(json::array()) == 1400);
  json scaled = everywhere;
  scaled["scale"] = 0.5;
  CHECK(total_of_cell_0(json::array({scaled})) == 700);
  json own = everywhere;
  own["D_m_nS"] = 100;  // D_m_side_nS unset: the region's D_m_nS
  CHECK(total_of_cell_0(json::array({own})) == 200);
  own["D_m_side_nS"] = 10;
  CHECK(total_of_cell_0(json::array({own})) == 110);
  // Overlapping, the last listed wins: `own` over cell 0's two junctions
  // (midpoints 94 and 125 um up), after the scaled region over all.
  own["y_mm"] = {-1, 0.3};
  CHECK(total_of_cell_0(json::array({scaled, own})) == 110);
}

TEST_CASE("coupling.regions: bad regions are named") {
  json m = paced_strand(10);
  const auto error_of = [&](const json& region) {
    m["coupling"]["regions"] = json::array({region});
    try {
      Simulation sim(parse_scene(m));
    } catch (const ManifestError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error_of({{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {0, 1}}, {"scale", 0.5}, {"D_m_nS", 1}}) ==
        "manifest: coupling.regions[0]: expected either scale or conductances (D_m_nS, D_m_side_nS, D_f_nS), got both");
  CHECK(error_of({{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {0, 1}}}) ==
        "manifest: coupling.regions[0]: expected scale or conductances (D_m_nS, D_m_side_nS, D_f_nS), got neither");
  CHECK(error_of({{"shape", "square"}, {"x_mm", {-1, 1}}, {"y_mm", {0, 1}}, {"scale", 1}}).find(
            "coupling.regions[0].shape") != std::string::npos);
  CHECK(error_of({{"shape", "rectangle"}, {"x_mm", {1, -1}}, {"y_mm", {0, 1}}, {"scale", 1}}) ==
        "manifest: coupling.regions[0].x_mm: expected min < max (within +-1e6 mm), got [1,-1]");
  // Off the strand (x = 0, y 0-1.25 mm): no junction's midpoint in it.
  CHECK(error_of({{"shape", "ellipse"}, {"x_mm", {2, 3}}, {"y_mm", {0, 1}}, {"scale", 1}}) ==
        "manifest: coupling.regions[0]: holds no junction (none has its midpoint in it and in no later region; its "
        "x_mm [2, 3], y_mm [0, 1]; the tissue spans x [-0.0125, 0.0125] mm, y [0, 1.25] mm)");
}

TEST_CASE("coupling.regions: a rank holding part of the graph names a region without junctions as one process does") {
  // A rank of a split run counts where the regions hold junctions as its
  // whole graph goes by (CouplingPlaces), and its Laplacian, of part of the
  // graph, checks nothing: the same error as the whole tissue's, and none
  // where every region holds a junction somewhere, if not in its rows.
  json m = paced_strand(10);
  const json on_strand = {{"shape", "rectangle"}, {"x_mm", {-1, 1}}, {"y_mm", {1.0, 1.3}}, {"scale", 0.5}};
  const json off_strand = {{"shape", "ellipse"}, {"x_mm", {2, 3}}, {"y_mm", {0, 1}}, {"scale", 1}};
  const JunctionConductances g_nS{1000, 1000, 0.3};
  for (const bool off : {false, true}) {
    CAPTURE(off);
    m["coupling"]["regions"] = off ? json::array({on_strand, off_strand}) : json::array({on_strand});
    const Scene scene = parse_scene(m);
    const Tissue whole = scene.tissue->build(scene.seed);
    std::string whole_error = "(no error)";
    try {
      junction_laplacian_nS(whole, g_nS, scene.coupling.regions);
    } catch (const ManifestError& e) {
      whole_error = e.what();
    }
    // Rank 0 of 2: the strand's first cells, away from the region.
    CouplingPlaces places(scene.coupling.regions, nullptr);
    std::shared_ptr<const CellStream> stream = stream_of(whole);
    Tissue part = stream->cell_types();
    const PartialGraphCut cut =
        cut_without_graph(part, 2, 0, stream, [&](const CellCentre& a, const CellCentre& b) { places.count(a, b); });
    std::string part_error = "(no error)";
    try {
      places.check(part);
    } catch (const ManifestError& e) {
      part_error = e.what();
    }
    CHECK(part_error == whole_error);
    CHECK((whole_error == "(no error)") == !off);
    const CellNumbering held(part.cell_count(),
                             rank_cells(
                                 part, 2, [&](int cell) { return part_by_cuts(cut.cuts, part, cell); }, 0));
    CHECK_NOTHROW(junction_laplacian_nS(part, g_nS, scene.coupling.regions, nullptr, &held));
  }
}
