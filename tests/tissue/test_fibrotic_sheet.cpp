// The `fibrotic_sheet` builder (core/tissue/builders/fibrotic_sheet.cpp) and
// its fibrosis patterns (core/tissue/fibrosis_pattern.cpp): the brick layout,
// the density each pattern achieves, the patchy pattern's correlation length,
// interstitial lines along the fibres, collagen that carries no coupling,
// determinism for a seed, errors that name the JSON path, its cells built
// alone for a split run (TissueBuilder::build_cells); mechanics builds on it
// (tests/mechanics/test_dem_sheets.cpp tests the DEM body).
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <set>

#include "run/simulation.hpp"
#include "scene/scene.hpp"
#include "support/scenes.hpp"
#include "tissue/builders/column_tissue.hpp"
#include "tissue/tissue_builder.hpp"
#include "util/json_reader.hpp"

using namespace fibrodem;

namespace {

json sheet(double width_mm, double length_mm, const json& fibrosis = json()) {
  json t = {{"builder", "fibrotic_sheet"}, {"width_mm", width_mm}, {"length_mm", length_mm}};
  if (!fibrosis.is_null()) t["fibrosis"] = fibrosis;
  return t;
}

const double kPitchX = kColumnPitch_um, kPitchY = kMyocyteLength_um;

// Grid slot (column, row) of a cell, from its centre (odd columns sit half a cell up).
std::pair<int, int> slot_of(const Tissue& t, std::size_t cell) {
  const int c = static_cast<int>(std::lround(t.x_um[cell] / kPitchX - 0.5));
  const int r = static_cast<int>(std::lround(t.y_um[cell] / kPitchY - 0.5 - 0.5 * (c % 2)));
  return {c, r};
}

// Fibrotic slots as a grid (1: fibrotic), from a build with `as: fibroblasts`.
struct SlotGrid {
  int columns = 0, rows = 0;
  std::vector<char> v;
  char at(int c, int r) const { return v[static_cast<std::size_t>(c) * rows + r]; }
};
SlotGrid fibroblast_grid(const Tissue& t) {
  SlotGrid g;
  for (std::size_t i = 0; i < t.cell_count(); ++i) {
    const auto [c, r] = slot_of(t, i);
    g.columns = std::max(g.columns, c + 1);
    g.rows = std::max(g.rows, r + 1);
  }
  g.v.assign(static_cast<std::size_t>(g.columns) * g.rows, 0);
  for (std::size_t i = 0; i < t.cell_count(); ++i) {
    const auto [c, r] = slot_of(t, i);
    g.v[static_cast<std::size_t>(c) * g.rows + r] = t.type[i] == CellType::fibroblast;
  }
  return g;
}

double fibroblast_fraction(const Tissue& t) {
  return static_cast<double>(t.count(CellType::fibroblast)) / static_cast<double>(t.cell_count());
}

bool same_tissue(const Tissue& a, const Tissue& b) {
  return a.type == b.type && a.x_um == b.x_um && a.y_um == b.y_um && a.cell_edges == b.cell_edges;
}

bool lateral(const Tissue& t, const std::pair<int, int>& e) {
  return std::abs(t.x_um[e.first] - t.x_um[e.second]) > 1.0;
}

}  // namespace

TEST_CASE("fibrotic_sheet: a brick wall of myocytes, 6 neighbours inside, one connected graph") {
  // 1.0 x 2.0 mm: floor(1000 / 23.57) = 42 columns; odd columns start 62.5 um
  // up, so floor((2000 - 62.5) / 125) = 15 rows.
  const Tissue t = testing::build_tissue(sheet(1.0, 2.0));
  CHECK(t.cell_count() == 42 * 15);
  CHECK(t.count(CellType::fibroblast) == 0);
  // The paper's particles (7 per myocyte), bonded where they touch: each end
  // particle to the next cell's, and 3 particles to 3 of each side neighbour
  // (23.57 um across, 4.17 um along: 1.06 um overlap).
  CHECK(t.particles.size() == 7 * t.cell_count());
  CHECK(t.bonds.size() == 14 * 42 + 3 * (2 * 15 - 1) * 41);
  // Edges: 41 end-to-end per column... 14 per column x 42, plus 2 per cell
  // beside the next column except the one row that has a single neighbour
  // there: (2 * 15 - 1) per column pair x 41.
  CHECK(t.cell_edges.size() == 14 * 42 + (2 * 15 - 1) * 41);
  std::vector<int> degree(t.cell_count(), 0);
  for (const auto& [i, j] : t.cell_edges) {
    CHECK(i < j);
    ++degree[i];
    ++degree[j];
    // Neighbours: the next cell along the column, or beside it, overlapping by half a cell.
    const double dx = std::abs(t.x_um[i] - t.x_um[j]), dy = std::abs(t.y_um[i] - t.y_um[j]);
    const bool along = dx < 1e-9 && std::abs(dy - kPitchY) < 1e-9;
    const bool beside = std::abs(dx - kPitchX) < 1e-9 && std::abs(dy - kPitchY / 2) < 1e-9;
    CHECK((along || beside));
  }
  for (std::size_t i = 0; i < t.cell_count(); ++i) {
    const auto [c, r] = slot_of(t, i);
    if (c > 0 && c < 41 && r > 0 && r < 14) CHECK(degree[i] == 6);
  }
  CHECK(cell_graph_components(t).count() == 1);
  const auto b = t.bounds_um();
  CHECK(b[1] <= 1000.0);
  CHECK(b[3] <= 2000.0);
}

TEST_CASE("fibrotic_sheet: each pattern reaches its density") {
  // 5 x 5 mm: 212 columns x 39 rows = 8268 slots. Density 0.2.
  const double density = 0.2;
  const double slots = 212.0 * 39.0;
  CHECK(testing::build_tissue(sheet(5, 5)).cell_count() == 212 * 39);
  // diffuse: independent draws, binomial; sd sqrt(0.2 * 0.8 / 8268) = 0.0044, tolerance 4.5 sd.
  // patchy, interstitial: exactly round(0.2 * 8268) slots (1654), tolerance one slot.
  // compact: slots whose centres fall in the rectangle; the edge rounds by at most half
  // a cell on each side: perimeter/2 in cells ~ (2236 / 23.57 + 2236 / 125) = 113 of
  // 8268 bounds the error, tolerance 0.014.
  const std::map<std::string, double> tolerance = {
      {"diffuse", 0.02}, {"patchy", 1.0 / slots}, {"interstitial", 1.0 / slots}, {"compact", 0.014}};
  for (const auto& entry : tolerance) {
    const std::string& pattern = entry.first;  // (not a structured binding: clang's CAPTURE cannot take one)
    const double tol = entry.second;
    CAPTURE(pattern);
    const Tissue f = testing::build_tissue(sheet(5, 5, {{"density", density}, {"pattern", pattern}, {"as", "fibroblasts"}}), 4);
    CHECK(f.cell_count() == 212 * 39);
    CHECK(std::abs(fibroblast_fraction(f) - density) <= tol + 1e-12);
    if (pattern == "interstitial") continue;  // collagen: septa, not holes (next test)
    const Tissue c = testing::build_tissue(sheet(5, 5, {{"density", density}, {"pattern", pattern}, {"as", "collagen"}}), 4);
    CHECK(c.count(CellType::fibroblast) == 0);
    CHECK(slots - static_cast<double>(c.cell_count()) == static_cast<double>(f.count(CellType::fibroblast)));
  }
  // Density 0: the plain sheet, whatever the pattern.
  const Tissue none = testing::build_tissue(sheet(5, 5, {{"density", 0.0}, {"pattern", "patchy"}}));
  CHECK(none.cell_count() == 212 * 39);
}

TEST_CASE("fibrotic_sheet: collagen cells carry no coupling") {
  const json fibrosis = {{"density", 0.3}, {"pattern", "diffuse"}};
  json as_fibroblasts = fibrosis, as_collagen = fibrosis;
  as_fibroblasts["as"] = "fibroblasts";
  as_collagen["as"] = "collagen";
  const Tissue f = testing::build_tissue(sheet(2, 2, as_fibroblasts), 9), c = testing::build_tissue(sheet(2, 2, as_collagen), 9);
  // Same seed, same fibrotic slots: collagen leaves exactly the fibroblasts' slots empty ...
  std::set<std::pair<double, double>> fibrotic, present;
  for (std::size_t i = 0; i < f.cell_count(); ++i)
    if (f.type[i] == CellType::fibroblast) fibrotic.insert({f.x_um[i], f.y_um[i]});
  for (std::size_t i = 0; i < c.cell_count(); ++i) present.insert({c.x_um[i], c.y_um[i]});
  CHECK(present.size() + fibrotic.size() == f.cell_count());
  for (const auto& p : fibrotic) CHECK(present.count(p) == 0);
  // ... and the remaining cells keep exactly the myocyte-myocyte couplings of the fibroblast build.
  std::set<std::pair<std::pair<double, double>, std::pair<double, double>>> mm_f, edges_c;
  for (const auto& [i, j] : f.cell_edges)
    if (f.type[i] == CellType::myocyte && f.type[j] == CellType::myocyte)
      mm_f.insert({{f.x_um[i], f.y_um[i]}, {f.x_um[j], f.y_um[j]}});
  for (const auto& [i, j] : c.cell_edges) edges_c.insert({{c.x_um[i], c.y_um[i]}, {c.x_um[j], c.y_um[j]}});
  CHECK(mm_f == edges_c);
  // As fibroblasts, the fibrotic cells are coupled (to a fibroblast model via D_f).
  std::size_t fibroblast_edges = 0;
  for (const auto& [i, j] : f.cell_edges)
    if (f.type[i] == CellType::fibroblast || f.type[j] == CellType::fibroblast) ++fibroblast_edges;
  CHECK(fibroblast_edges > 2 * f.count(CellType::fibroblast));
}

TEST_CASE("fibrotic_sheet: interstitial fibrosis runs in lines along the fibres") {
  const json lines = {{"density", 0.15}, {"pattern", "interstitial"}, {"line_length_mm", 0.5}};
  json as_fibroblasts = lines;
  as_fibroblasts["as"] = "fibroblasts";
  const Tissue f = testing::build_tissue(sheet(4, 6, as_fibroblasts), 3);
  const SlotGrid g = fibroblast_grid(f);
  // Mean run of fibrotic slots along a column (fibre) and along a row (across
  // fibres, same-parity columns two apart, so rows line up): lines of 0.5 mm =
  // 4 cells give runs of ~4 along (merged lines longer, lines cut at the sheet's
  // ends shorter); across, runs stay near 1 (by chance 1 / (1 - 0.15) = 1.18).
  auto mean_run = [&](bool along) {
    double cells = 0, runs = 0;
    const int outer = along ? g.columns : g.rows, inner = along ? g.rows : g.columns;
    for (int a = 0; a < outer; ++a)
      for (int parity = 0; parity < (along ? 1 : 2); ++parity) {
        bool in = false;
        for (int b = along ? 0 : parity; b < inner; b += along ? 1 : 2) {
          const char s = along ? g.at(a, b) : g.at(b, a);
          if (s) ++cells;
          if (s && !in) ++runs;
          in = s;
        }
      }
    return cells / runs;
  };
  const double along = mean_run(true), across = mean_run(false);
  CAPTURE(along);
  CAPTURE(across);
  CHECK(along >= 3.5);
  CHECK(along <= 5.5);
  CHECK(across <= 1.35);
  // As collagen: the same slots keep their myocytes and their couplings along
  // the fibre, and lose every side-to-side coupling (the septa).
  json as_collagen = lines;
  as_collagen["as"] = "collagen";
  const Tissue c = testing::build_tissue(sheet(4, 6, as_collagen), 3);
  const Tissue plain = testing::build_tissue(sheet(4, 6));
  REQUIRE(c.cell_count() == plain.cell_count());
  CHECK(c.count(CellType::fibroblast) == 0);
  CHECK(c.x_um == f.x_um);  // same slots, same cell numbering
  std::size_t along_c = 0, along_plain = 0;
  std::set<std::pair<int, int>> kept(c.cell_edges.begin(), c.cell_edges.end());
  for (const auto& e : plain.cell_edges) {
    const bool line = f.type[e.first] == CellType::fibroblast || f.type[e.second] == CellType::fibroblast;
    if (!lateral(plain, e)) ++along_plain;
    if (lateral(plain, e)) CHECK(kept.count(e) == static_cast<std::size_t>(!line));
  }
  for (const auto& e : c.cell_edges) along_c += !lateral(c, e);
  CHECK(along_c == along_plain);
}

TEST_CASE("fibrotic_sheet: patchy fibrosis has the requested correlation length") {
  // Thresholding a Gaussian field of autocorrelation rho(d) = exp(-d^2 / l^2)
  // at its median gives a 0/1 pattern of autocorrelation (2 / pi) asin(rho(d))
  // (the arcsine law for clipped Gaussian processes, Van Vleck & Middleton
  // 1966 Proc IEEE 54:2): 0.569 at d = l/2, 0.240 at d = l, 0.012 at d = 2l.
  // Measured with l = 0.5 mm, density 0.5, averaged over 4 seeds of a 24 x 24 mm
  // sheet (1018 x 191 slots). One 12 x 12 mm sheet scatters by ~0.045 about the
  // law (measured over seeds 1-5), so the average by ~0.012; tolerance 0.05,
  // which also covers the field's discretisation (sigma = 2 cells along y).
  const double l_um = 500;
  const std::vector<std::pair<int, int>> lags = {{0, 2}, {0, 4}, {0, 8}, {10, 0}, {22, 0}, {42, 0}};
  std::vector<double> mean(lags.size(), 0.0);
  const int seeds = 4;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Tissue t = testing::build_tissue(sheet(24, 24, {{"density", 0.5}, {"pattern", "patchy"}, {"correlation_length_mm", 0.5},
                                           {"as", "fibroblasts"}}), seed);
    const SlotGrid g = fibroblast_grid(t);
    const double p = fibroblast_fraction(t);
    for (std::size_t k = 0; k < lags.size(); ++k) {
      const auto [dc, dr] = lags[k];
      double sum = 0, n = 0;
      for (int c = 0; c + dc < g.columns; ++c)
        for (int r = 0; r + dr < g.rows; ++r, ++n) sum += (g.at(c, r) - p) * (g.at(c + dc, r + dr) - p);
      mean[k] += sum / n / (p * (1 - p)) / seeds;
    }
  }
  // Along the fibres, lags of 2, 4, 8 rows (250, 500, 1000 um); across, even lags
  // (same-parity columns, no stagger) of 10, 22, 42 columns (236, 519, 990 um).
  for (std::size_t k = 0; k < lags.size(); ++k) {
    const double d_um = lags[k].first * kPitchX + lags[k].second * kPitchY;
    const double expected = 2 / M_PI * std::asin(std::exp(-d_um * d_um / (l_um * l_um)));
    CAPTURE(d_um);
    CAPTURE(mean[k]);
    CHECK(std::abs(mean[k] - expected) <= 0.05);
  }
  // A diffuse pattern of the same density has no correlation at one cell's lag.
  const Tissue d = testing::build_tissue(sheet(12, 12, {{"density", 0.5}, {"pattern", "diffuse"}, {"as", "fibroblasts"}}), 7);
  const SlotGrid gd = fibroblast_grid(d);
  double sum = 0, n = 0;
  for (int c = 0; c < gd.columns; ++c)
    for (int r = 0; r + 1 < gd.rows; ++r, ++n) sum += (gd.at(c, r) - 0.5) * (gd.at(c, r + 1) - 0.5);
  CHECK(std::abs(sum / n / 0.25) <= 0.05);
}

TEST_CASE("fibrotic_sheet: compact is one solid rectangle, the Fig. 8 patch a special case") {
  // fibrotic_patch's defaults (in_series): a 0.6 x 1.0 mm patch centred in 2.32
  // x 6.27 mm. As a compact pattern: density 0.6 / (2.32 * 6.27), aspect 1.0/0.6.
  const double density = 0.6 * 1.0 / (2.32 * 6.27);
  const Tissue t = testing::build_tissue(sheet(2.32, 6.27, {{"density", density}, {"pattern", "compact"}, {"aspect", 1.0 / 0.6},
                                             {"as", "fibroblasts"}}));
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (std::size_t i = 0; i < t.cell_count(); ++i)
    if (t.type[i] == CellType::fibroblast) {
      x0 = std::min(x0, t.x_um[i]), x1 = std::max(x1, t.x_um[i]);
      y0 = std::min(y0, t.y_um[i]), y1 = std::max(y1, t.y_um[i]);
    }
  // The sheet holds 98 columns (2310 um) of 49 rows ((49 + 0.5) x 125 = 6187.5 um
  // with the odd columns' shift), so the patch is centred at (1155, 3094) um; its
  // area is density x that (0.589 mm^2 against 0.6: the sheet is whole cells).
  // Its outermost cell centres lie within a pitch of the 0.6 x 1.0 mm rectangle's edges.
  const double cx = 98 * kPitchX / 2, cy = 49.5 * kPitchY / 2;
  CHECK(std::abs(x0 - (cx - 300)) <= kPitchX);
  CHECK(std::abs(x1 - (cx + 300)) <= kPitchX);
  CHECK(std::abs(y0 - (cy - 500)) <= kPitchY);
  CHECK(std::abs(y1 - (cy + 500)) <= kPitchY);
  // Solid: every slot inside the fibroblasts' bounding box is a fibroblast.
  for (std::size_t i = 0; i < t.cell_count(); ++i)
    if (t.x_um[i] >= x0 && t.x_um[i] <= x1 && t.y_um[i] >= y0 && t.y_um[i] <= y1)
      CHECK(t.type[i] == CellType::fibroblast);
  // The region does not depend on the seed.
  const json spec = sheet(2.32, 6.27, {{"density", density}, {"pattern", "compact"}, {"aspect", 1.0 / 0.6}});
  CHECK(same_tissue(testing::build_tissue(spec, 1), testing::build_tissue(spec, 2)));
}

TEST_CASE("fibrotic_sheet: same seed, same tissue, another seed, another tissue") {
  for (const std::string pattern : {"diffuse", "patchy", "interstitial"})
    for (const std::string as : {"fibroblasts", "collagen"}) {
      CAPTURE(pattern);
      CAPTURE(as);
      const json spec = sheet(1.5, 3, {{"density", 0.25}, {"pattern", pattern}, {"as", as}});
      const Tissue a = testing::build_tissue(spec, 11), b = testing::build_tissue(spec, 11), c = testing::build_tissue(spec, 12);
      CHECK(same_tissue(a, b));
      CHECK_FALSE(same_tissue(a, c));
    }
}

TEST_CASE("fibrotic_sheet: bad values are rejected with their JSON path") {
  auto with = [](const json& fibrosis) { return sheet(1, 1, fibrosis); };
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"density", 1.0}, {"pattern", "diffuse"}})),
                       doctest::Contains("tissue.fibrosis.density: expected a fraction of cells in [0, 1), got 1"),
                       ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"density", -0.1}, {"pattern", "diffuse"}})),
                       doctest::Contains("tissue.fibrosis.density"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"density", 0.1}, {"pattern", "blotchy"}})),
                       doctest::Contains("tissue.fibrosis.pattern"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"density", 0.1}, {"pattern", "diffuse"}, {"as", "scar"}})),
                       doctest::Contains("tissue.fibrosis.as"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"pattern", "diffuse"}})), doctest::Contains("tissue.fibrosis.density"),
                       ManifestError);
  // A key of another pattern is an unknown key here.
  CHECK_THROWS_WITH_AS(testing::build_tissue(with({{"density", 0.1}, {"pattern", "diffuse"}, {"correlation_length_mm", 1}})),
                       doctest::Contains("tissue.fibrosis.correlation_length_mm"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue({{"builder", "fibrotic_sheet"}, {"width_mm", 1}}), doctest::Contains("tissue.length_mm"),
                       ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue(sheet(1, 1, {{"density", 0.1}, {"pattern", "compact"}, {"aspect", 0}})),
                       doctest::Contains("tissue.fibrosis.aspect"), ManifestError);
}

TEST_CASE("fibrotic_sheet: mechanics builds on it") {
  const json manifest = json::parse(R"({
    "fibrodem": 1, "name": "sheet_mechanics", "duration_ms": 1,
    "effects": ["electrophysiology", "coupling", "contraction", "mechanics"],
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 0.2, "length_mm": 0.5},
    "cells": {"myocyte": {"model": "colman", "myofilament": {"model": "rice"}}},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01}
  })");
  Simulation sim{parse_scene(manifest)};
  CHECK(sim.processes().has("mechanics"));
  sim.run();
  CHECK(sim.summary().contains("peak_strain"));
}

namespace {

// What build_cells, stream_cells, cell_count and for_each_particle give
// against build(): the same cells and graph (the stream's cells and edges
// one by one in their order, each edge's ends with their centres), the cell
// count, the particles' and bonds' counts and bounds, and the particles
// themselves in their order, to the bit.
void check_cells_alone(const TissueBuilder& builder, std::uint64_t seed) {
  const Tissue whole = builder.build(seed);
  const Tissue cells = builder.build_cells(seed);
  CHECK(same_tissue(cells, whole));
  const std::unique_ptr<CellStream> stream = builder.stream_cells(seed);
  Tissue streamed_cells = stream->cell_types();
  CHECK(streamed_cells.type == whole.type);
  CHECK(streamed_cells.x_um.empty());
  CHECK(streamed_cells.cell_edges.empty());
  CHECK(streamed_cells.built_particles() == whole.built_particles());
  CHECK(streamed_cells.built_bonds() == whole.built_bonds());
  CHECK(streamed_cells.bounds_um() == whole.bounds_um());
  stream->for_each_cell([&](int cell, CellType type, double x_um, double y_um) {
    CHECK(cell == static_cast<int>(streamed_cells.x_um.size()));
    CHECK(type == whole.type.at(static_cast<std::size_t>(cell)));
    streamed_cells.x_um.push_back(x_um);
    streamed_cells.y_um.push_back(y_um);
  });
  std::size_t misplaced_ends = 0;
  stream->for_each_edge([&](const CellCentre& a, const CellCentre& b) {
    streamed_cells.cell_edges.emplace_back(a.cell, b.cell);
    for (const CellCentre& end : {a, b}) {
      const auto i = static_cast<std::size_t>(end.cell);
      misplaced_ends += end.x_um != whole.x_um.at(i) || end.y_um != whole.y_um.at(i);
    }
  });
  CHECK(misplaced_ends == 0);
  CHECK(streamed_cells.cell_edges == whole.cell_edges);
  CHECK(builder.cell_count(seed) == whole.cell_count());
  CHECK(same_tissue(streamed_cells, whole));
  CHECK(cells.particles_released());
  CHECK(cells.particles.empty());
  CHECK(cells.bonds.empty());
  CHECK(cells.collagen.empty());
  CHECK(cells.collagen_bonds.empty());
  CHECK(cells.built_particles() == whole.built_particles());
  CHECK(cells.built_bonds() == whole.built_bonds());
  CHECK(cells.bounds_um() == whole.bounds_um());
  std::vector<Particle> streamed;
  builder.for_each_particle(seed, [&streamed](const Particle& p) { streamed.push_back(p); });
  REQUIRE(streamed.size() == whole.particles.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < streamed.size(); ++i) {
    const Particle &a = streamed[i], &b = whole.particles[i];
    differ += a.x_um != b.x_um || a.y_um != b.y_um || a.r_um != b.r_um || a.cell != b.cell;
  }
  CHECK(differ == 0);
}

std::unique_ptr<TissueBuilder> builder_of(const json& spec) {
  JsonReader reader(spec, "tissue");
  return make_tissue_builder(reader);
}

}  // namespace

TEST_CASE("fibrotic_sheet: its cells alone, and its particles one by one, are those of the whole tissue") {
  // Every kind of slot (myocyte, fibroblast, collagen disks, void) and of
  // junction (through collagen, across a septum), on an odd and even
  // column count and on one column. (Premise: each variant gives the
  // kinds it is here for.)
  const std::vector<json> variants = {
      sheet(1.0, 1.5),
      sheet(1.0, 1.5, {{"density", 0.2}, {"pattern", "diffuse"}, {"as", "fibroblasts"}}),
      sheet(1.0, 1.5, {{"density", 0.2}, {"pattern", "diffuse"}}),
      sheet(0.99, 1.5, {{"density", 0.3}, {"pattern", "patchy"}, {"collagen", "particles"}}),
      sheet(1.0, 1.5, {{"density", 0.2}, {"pattern", "interstitial"}, {"collagen", "particles"}}),
      sheet(1.0, 1.5, {{"density", 0.1}, {"pattern", "compact"}, {"as", "fibroblasts"}}),
      sheet(0.025, 1.5),
  };
  for (const json& spec : variants) {
    INFO(spec.dump());
    const auto builder = builder_of(spec);
    CHECK(builder->builds_cells_alone());
    check_cells_alone(*builder, 3);
  }
  const Tissue with_fibroblasts = testing::build_tissue(variants[1], 3);
  CHECK(with_fibroblasts.count(CellType::fibroblast) > 0);
  const Tissue with_voids = testing::build_tissue(variants[2], 3);
  CHECK(with_voids.cell_count() < with_fibroblasts.cell_count());
  const Tissue with_collagen = testing::build_tissue(variants[3], 3);
  CHECK(!with_collagen.collagen.empty());
  const Tissue with_septa = testing::build_tissue(variants[4], 3);
  CHECK(!with_septa.collagen_bonds.empty());
  CHECK(with_septa.collagen.empty());
}

TEST_CASE("a builder without its own build_cells: the whole tissue's, released") {
  const auto builder = builder_of({{"builder", "in_series"}, {"width_mm", 0.3}, {"height_mm", 0.6}, {"fm_ratio", 0.3}});
  CHECK(!builder->builds_cells_alone());
  check_cells_alone(*builder, 5);
}
