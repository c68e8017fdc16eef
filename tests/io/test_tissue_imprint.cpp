// A tissue's imprint (io/tissue_imprint.hpp): what rank 0 of a split run
// keeps of the particles in their place. The reference is the same tissue
// with its particles: every picture and VTK XML file made from the imprint
// must be the file made from the particles, byte for byte.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "io/tissue_imprint.hpp"
#include "io/tissue_picture.hpp"
#include "io/vtk_xml_writer.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_SUITE_BEGIN("io");

namespace {

// Interstitial tissue: fibroblasts among myocytes placed with random offsets,
// so that particles of different cells overlap in many ways.
Tissue irregular_tissue(double side_mm = 1.5) {
  return testing::build_tissue({{"builder", "interstitial"}, {"width_mm", side_mm}, {"height_mm", side_mm}}, 3);
}

Tissue released(const Tissue& tissue) {
  Tissue copy = tissue;
  copy.release_particles(imprint_tissue(tissue));
  return copy;
}

// A value per cell that changes from each cell to the next, so that a pixel
// given another cell's colour shows.
std::vector<double> cell_values(const Tissue& tissue) {
  std::vector<double> v(tissue.cell_count());
  for (std::size_t c = 0; c < v.size(); ++c) v[c] = -85 + 120 * std::fmod(0.37 * static_cast<double>(c), 1.0);
  return v;
}

// A snapshot's picture (tissue_snapshots.cpp): titled, at the undeformed
// tissue's scale, without antialiasing.
PictureOptions snapshot_options(const Tissue& tissue) {
  PictureOptions o;
  o.title = "snapshot   t = 12.0 ms";
  o.value_label = "V (mV)";
  o.value_min = -90;
  o.value_max = 40;
  const auto box = tissue.bounds_um();
  o.pixels_per_um = PictureOptions{}.height_px / std::max(box[3] - box[2], 1.0);
  o.antialias = false;
  return o;
}

std::string png_of(const Tissue& tissue, const std::string& name, const std::vector<double>* values,
                   const PictureOptions& options) {
  const auto file = testing::scratch_dir("tissue_imprint") / name;
  write_tissue_png(tissue, file, values, options);
  return testing::read_file(file);
}

}  // namespace

TEST_CASE("a released tissue's pictures are drawn from its imprint, the particles' pixels") {
  const Tissue tissue = irregular_tissue();
  REQUIRE(tissue.count(CellType::fibroblast) > 0);
  const Tissue imprinted = released(tissue);
  REQUIRE(imprinted.particles.empty());
  REQUIRE(imprinted.imprint() != nullptr);
  const std::vector<double> values = cell_values(tissue);

  SUBCASE("a snapshot coloured by value") {
    const PictureOptions o = snapshot_options(tissue);
    const std::string from_particles = png_of(tissue, "particles.png", &values, o);
    CHECK(png_of(imprinted, "imprint.png", &values, o) == from_particles);
    // The premise: the colours differ cell by cell (one value for all would draw another picture).
    const std::vector<double> flat(values.size(), 0.0);
    CHECK(png_of(tissue, "flat.png", &flat, o) != from_particles);
  }
  SUBCASE("by cell type, narrower (no colour bar), with a path over the cells") {
    PictureOptions o = snapshot_options(tissue);
    o.paths.push_back({{100, 700, 900}, {200, 800, 1300}, true});
    CHECK(png_of(imprinted, "imprint.png", nullptr, o) == png_of(tissue, "particles.png", nullptr, o));
  }
  SUBCASE("a map at the default scale: antialiasing asked for, drawn without") {
    PictureOptions o;
    o.title = "activation map";
    CHECK(o.antialias);
    const std::string from_imprint = png_of(imprinted, "imprint.png", &values, o);
    CHECK(from_imprint != png_of(tissue, "smooth.png", &values, o));
    o.antialias = false;
    CHECK(from_imprint == png_of(tissue, "particles.png", &values, o));
  }
  SUBCASE("what the imprint cannot draw is refused") {
    PictureOptions untitled = snapshot_options(tissue);
    untitled.title.clear();
    CHECK_THROWS_WITH_AS(png_of(imprinted, "x.png", &values, untitled),
                         doctest::Contains("holds the picture with a title at the default scale only"),
                         std::logic_error);
    PictureOptions larger = snapshot_options(tissue);
    larger.pixels_per_um *= 2;
    CHECK_THROWS_AS(png_of(imprinted, "x.png", &values, larger), std::logic_error);
    PictureOptions bonds = snapshot_options(tissue);
    bonds.draw_bonds = true;
    CHECK_THROWS_WITH_AS(png_of(imprinted, "x.png", &values, bonds), doctest::Contains("no bonds to draw"),
                         std::logic_error);
  }
}

TEST_CASE("a released tissue's VTK XML file is written from its imprint, the same bytes") {
  const Tissue tissue = irregular_tissue(2.5);
  // More than one 64 kB block in the points' array (12 bytes a particle).
  REQUIRE(tissue.particles.size() * 12 > 2 * 65536);
  const Tissue imprinted = released(tissue);
  const auto dir = testing::scratch_dir("tissue_imprint_vtp");
  std::vector<double> V = cell_values(tissue), apd(V.size());
  for (std::size_t c = 0; c < apd.size(); ++c) apd[c] = 200 + static_cast<double>(c % 17);
  const CellFields fields{{"V_mV", V}, {"apd90 ms", apd}};

  write_tissue_vtp(tissue, dir / "particles.vtp", fields, false);
  write_tissue_vtp(imprinted, dir / "imprint.vtp", fields, false);
  CHECK(testing::read_file(dir / "imprint.vtp") == testing::read_file(dir / "particles.vtp"));
  // Without fields, and twice from one imprint (its runs are read afresh).
  write_tissue_vtp(tissue, dir / "bare.vtp", {}, false);
  for (int k = 0; k < 2; ++k) {
    write_tissue_vtp(imprinted, dir / "bare_imprint.vtp", {}, false);
    CHECK(testing::read_file(dir / "bare_imprint.vtp") == testing::read_file(dir / "bare.vtp"));
  }
  // The premise: the fields are in the file (a file without them differs).
  CHECK(testing::read_file(dir / "bare.vtp") != testing::read_file(dir / "particles.vtp"));

  CHECK_THROWS_WITH_AS(write_tissue_vtp(imprinted, dir / "x.vtp", fields, true),
                       doctest::Contains("holds neither bonds nor displacements"), std::logic_error);
  const std::vector<std::array<double, 2>> displacement(tissue.particles.size(), {0.0, 0.0});
  CHECK_THROWS_AS(write_tissue_vtp(imprinted, dir / "x.vtp", fields, false, &displacement), std::logic_error);
  CHECK_THROWS_WITH_AS(write_tissue_vtp(imprinted, dir / "x.vtp", {{"short", {1.0, 2.0}}}, false),
                       doctest::Contains("has 2 values for"), std::runtime_error);
}

TEST_CASE("a tissue's imprint: runs of the particles' cells and its size") {
  const Tissue tissue = irregular_tissue();
  const auto imprint = imprint_tissue(tissue);
  const ParticleCellRuns& runs = imprint->cells;
  REQUIRE(runs.particles() == tissue.particles.size());
  std::size_t p = 0;
  for (std::size_t k = 0; k < runs.cell.size(); ++k)
    for (; p < static_cast<std::size_t>(runs.end[k]); ++p) REQUIRE(tissue.particles[p].cell == runs.cell[k]);
  // A myocyte's seven particles are one run: a run per cell here.
  CHECK(runs.cell.size() == tissue.cell_count());
  // The pixels and packed arrays are smaller than the particles and bonds they stand for.
  const double held =
      static_cast<double>(sizeof(Particle) * tissue.particles.size() + sizeof(Bond) * tissue.bonds.size());
  CHECK(imprint->vtp.bytes() < held);
  const PictureFrame& f = imprint->picture.frame;
  CHECK(imprint->picture.cell.size() == static_cast<std::size_t>(f.width_px) * static_cast<std::size_t>(f.height_px));
}

TEST_SUITE_END();
