// The seed paper's tissue builders (in_series, interstitial, fibrotic_patch):
// counts and F-M ratios against the requested ones, overlaps only where
// allowed, a connected cell graph, determinism per seed; and the tissue
// picture (PNG) and VTK writers.
#include <doctest/doctest.h>
#include <png.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "io/tissue_picture.hpp"
#include "io/vtk_writer.hpp"
#include "support/scenes.hpp"
#include "tissue/builders/column_tissue.hpp"

using namespace fibrodem;

namespace {

double fm_ratio(const Tissue& t) {
  return static_cast<double>(t.count(CellType::fibroblast)) /
         static_cast<double>(t.count(CellType::myocyte));
}

// Deepest overlap between particles of different cells placed by the column
// generator (particles of radius 12.5 um; the small interstitial fill is checked
// separately).
struct Overlaps {
  double between_placed_cells = 0;  // between particles of radius 12.5 um of two cells
  double along_fibre = 0;           // the same, for particles in one column (same x)
};

Overlaps deepest_overlaps(const Tissue& t) {
  Overlaps o;
  // Brute force over a bin grid of 30 um (all radii here <= 12.5 um).
  std::map<std::pair<int, int>, std::vector<int>> bins;
  auto key = [](double x, double y) {
    return std::make_pair(static_cast<int>(std::floor(x / 30)), static_cast<int>(std::floor(y / 30)));
  };
  for (int i = 0; i < static_cast<int>(t.particles.size()); ++i)
    bins[key(t.particles[i].x_um, t.particles[i].y_um)].push_back(i);
  for (int i = 0; i < static_cast<int>(t.particles.size()); ++i) {
    const Particle& p = t.particles[i];
    const auto [bx, by] = key(p.x_um, p.y_um);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        auto it = bins.find({bx + dx, by + dy});
        if (it == bins.end()) continue;
        for (int j : it->second) {
          if (j <= i) continue;
          const Particle& q = t.particles[j];
          if (p.cell == q.cell) continue;
          const double overlap = p.r_um + q.r_um - std::hypot(p.x_um - q.x_um, p.y_um - q.y_um);
          if (p.r_um < kParticleRadius_um || q.r_um < kParticleRadius_um) continue;
          o.between_placed_cells = std::max(o.between_placed_cells, overlap);
          if (std::abs(p.x_um - q.x_um) < 1e-9) o.along_fibre = std::max(o.along_fibre, overlap);
        }
      }
  }
  return o;
}

bool same_tissue(const Tissue& a, const Tissue& b) {
  if (a.type != b.type || a.particles.size() != b.particles.size() ||
      a.bonds.size() != b.bonds.size() || a.cell_edges != b.cell_edges)
    return false;
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    const Particle &p = a.particles[i], &q = b.particles[i];
    if (p.x_um != q.x_um || p.y_um != q.y_um || p.r_um != q.r_um || p.cell != q.cell) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("the column pitch, a compile-time constant, is sqrt((2r)^2 - (d/2)^2) to the last bit") {
  // 23.57 um: the seed paper's geometry (section 2.2.2), as std::sqrt gives it.
  const double r = kParticleRadius_um, d = kParticleSpacing_um;
  CHECK(kColumnPitch_um == std::sqrt(4 * r * r - d * d / 4));
  CHECK(kColumnPitch_um == doctest::Approx(23.5702).epsilon(1e-5));
}

TEST_CASE("in_series: the paper's tissue and F-M ratio, no overlap along a fibre, one connected graph") {
  // Paper (Fig. 3): 1.16 x 6.27 mm, ~2289 myocytes and 936 fibroblasts, F-M 0.41.
  const Tissue t = testing::build_tissue({{"builder", "in_series"}, {"width_mm", 1.16}, {"height_mm", 6.27},
                          {"fm_ratio", 0.41}}, 7);
  const auto m = t.count(CellType::myocyte), f = t.count(CellType::fibroblast);
  CHECK(m == doctest::Approx(2289).epsilon(0.05));  // random: +-5 %
  CHECK(f == doctest::Approx(936).epsilon(0.12));
  CHECK(fm_ratio(t) == doctest::Approx(0.41).epsilon(0.12));
  const auto b = t.bounds_um();
  CHECK(b[1] - b[0] <= 1160 + 1e-6);
  CHECK(b[3] - b[2] <= 6270 + 1e-6);
  for (const Particle& p : t.particles) CHECK(p.r_um == kParticleRadius_um);
  // Each fibroblast is one particle; each myocyte seven.
  std::vector<int> per_cell(t.cell_count(), 0);
  for (const Particle& p : t.particles) ++per_cell[p.cell];
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    CHECK(per_cell[c] == (t.type[c] == CellType::myocyte ? kMyocyteParticles : 1));
  const Overlaps o = deepest_overlaps(t);
  CHECK(o.along_fibre <= 1e-6);                               // cells touch end to end
  CHECK(o.between_placed_cells <= kAllowedOverlap_um + 1e-6);  // 1.43 um laterally at most
  const CellComponents comps = cell_graph_components(t);
  CHECK(comps.count() == 1);
  // Bonds join touching or overlapping particles of different cells only.
  for (const Bond& bd : t.bonds) {
    const Particle &p = t.particles[bd.p], &q = t.particles[bd.q];
    CHECK(p.cell != q.cell);
    CHECK(std::hypot(p.x_um - q.x_um, p.y_um - q.y_um) <= (p.r_um + q.r_um) * (1 + kTouchTolerance));
  }
  // Other ratios.
  for (double fm : {0.0, 0.11, 1.46}) {
    CAPTURE(fm);
    const Tissue u = testing::build_tissue({{"builder", "in_series"}, {"fm_ratio", fm}}, 3);
    CHECK(fm_ratio(u) == doctest::Approx(fm).epsilon(0.15).scale(1));
    CHECK(cell_graph_components(u).count() == 1);
  }
}

TEST_CASE("tissue builders: same seed, same tissue, another seed, another tissue") {
  for (const json& spec : {json{{"builder", "in_series"}, {"width_mm", 0.5}, {"height_mm", 2.0}},
                          json{{"builder", "interstitial"}, {"width_mm", 0.4}, {"height_mm", 1.5}},
                          json{{"builder", "fibrotic_patch"}, {"arrangement", "interstitial"},
                               {"width_mm", 0.8}, {"height_mm", 1.5}, {"patch_width_mm", 0.4},
                               {"patch_height_mm", 0.5}},
                          json{{"builder", "fibrotic_patch"}, {"arrangement", "in_series"},
                               {"width_mm", 0.8}, {"height_mm", 1.5}, {"patch_width_mm", 0.3},
                               {"patch_height_mm", 0.3}, {"patch_fibroblast_fraction", 0.5}}}) {
    CAPTURE(spec.dump());
    const Tissue a = testing::build_tissue(spec, 11), b = testing::build_tissue(spec, 11), c = testing::build_tissue(spec, 12);
    CHECK(same_tissue(a, b));
    CHECK_FALSE(same_tissue(a, c));
    CHECK(cell_graph_components(a).count() == 1);
  }
}

TEST_CASE("interstitial: the paper's example F-M 1.27, fibroblast particles never overlap before growth, "
          "rotated myocytes, connected graph") {
  const Tissue t = testing::build_tissue({{"builder", "interstitial"}}, 5);  // 1.16 x 6.27 mm
  CHECK(fm_ratio(t) == doctest::Approx(1.27).epsilon(0.1));
  CHECK(t.count(CellType::myocyte) > 1800);
  CHECK(cell_graph_components(t).count() == 1);
  double max_angle = 0;
  for (std::size_t i = 0; i + kMyocyteParticles <= t.particles.size();) {
    const Particle &bottom = t.particles[i];
    if (t.type[bottom.cell] != CellType::myocyte) break;  // myocytes come first
    const Particle& top = t.particles[i + kMyocyteParticles - 1];
    max_angle = std::max(max_angle, std::atan2(std::abs(top.x_um - bottom.x_um), top.y_um - bottom.y_um));
    i += kMyocyteParticles;
  }
  CHECK(max_angle > 8 * M_PI / 180);
  CHECK(max_angle <= 10 * M_PI / 180 + 1e-9);
  // Fibroblast particles: radii within [1, 4 * 1.5] um; several particles may form one fibroblast.
  std::size_t grouped = 0;
  std::vector<int> per_cell(t.cell_count(), 0);
  for (const Particle& p : t.particles) {
    ++per_cell[p.cell];
    if (t.type[p.cell] == CellType::fibroblast) {
      CHECK(p.r_um >= 1.0);
      CHECK(p.r_um <= 6.0 + 1e-9);
    }
  }
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::fibroblast && per_cell[c] > 1) ++grouped;
  CHECK(grouped > 0);
  // Growth "to_contact": no two particles of the fill overlap, and myocytes
  // overlap at most by the in-series lateral overlap.
  const Tissue u = testing::build_tissue({{"builder", "interstitial"}, {"width_mm", 0.5}, {"height_mm", 1.5},
                          {"growth", "to_contact"}}, 5);
  for (std::size_t i = 0; i < u.particles.size(); ++i)
    for (std::size_t j = i + 1; j < u.particles.size(); ++j) {
      const Particle &p = u.particles[i], &q = u.particles[j];
      if (p.cell == q.cell && u.type[p.cell] == CellType::myocyte) continue;
      const double overlap = p.r_um + q.r_um - std::hypot(p.x_um - q.x_um, p.y_um - q.y_um);
      const bool fill = u.type[p.cell] == CellType::fibroblast || u.type[q.cell] == CellType::fibroblast;
      if (fill) REQUIRE(overlap <= 1e-6 * (p.r_um + q.r_um));
      else REQUIRE(overlap <= kAllowedOverlap_um + 1e-6);
    }
  // Fewer fill attempts, fewer fibroblasts: the F-M ratio is steerable.
  const Tissue sparse = testing::build_tissue({{"builder", "interstitial"}, {"fill_attempts_per_um2", 0.02}}, 5);
  CHECK(fm_ratio(sparse) < 0.6 * fm_ratio(t));
}

TEST_CASE("fibrotic_patch: ~930 fibroblasts in a central patch, myocytes outside, connected") {
  for (const char* arrangement : {"in_series", "interstitial"}) {
    CAPTURE(arrangement);
    const Tissue t = testing::build_tissue({{"builder", "fibrotic_patch"}, {"arrangement", arrangement}}, 2);
    CHECK(t.count(CellType::fibroblast) == doctest::Approx(930).epsilon(0.12));
    const auto b = t.bounds_um();
    CHECK(b[1] - b[0] == doctest::Approx(2320).epsilon(0.01));
    CHECK(cell_graph_components(t).count() == 1);
    // All fibroblasts in the central region.
    for (std::size_t c = 0; c < t.cell_count(); ++c)
      if (t.type[c] == CellType::fibroblast) {
        REQUIRE(std::abs(t.x_um[c] - 1160) < 600);
        REQUIRE(std::abs(t.y_um[c] - 3135) < 800);
      }
  }
}

TEST_CASE("cell_graph_components finds isolated cells") {
  Tissue t;
  add_vertical_myocyte(t, 0, 0);
  add_vertical_myocyte(t, 0, kMyocyteLength_um);
  add_round_fibroblast(t, 500, 500);
  t.add_bond(kMyocyteParticles - 1, kMyocyteParticles);
  t.finalise();
  const CellComponents c = cell_graph_components(t);
  REQUIRE(c.count() == 2);
  CHECK(c.component == std::vector<int>{0, 0, 1});
  CHECK(c.size == std::vector<int>{2, 1});
  CHECK(c.largest() == 0);
}

TEST_CASE("add_myocyte rotates about the centre, add_vertical_myocyte is its straight case") {
  Tissue t;
  add_myocyte(t, 10, 20, M_PI / 2);  // axis along -x
  CHECK(t.particles.front().x_um == doctest::Approx(10 + kMyocyteEndOffset_um));
  CHECK(t.particles.back().x_um == doctest::Approx(10 - kMyocyteEndOffset_um));
  CHECK(t.particles.back().y_um == doctest::Approx(20));
  add_vertical_myocyte(t, 0, 0);
  CHECK(t.particles[kMyocyteParticles].y_um == doctest::Approx(kParticleRadius_um));
  CHECK(t.y_um[1] == doctest::Approx(kMyocyteLength_um / 2));
}

TEST_CASE("tissue builders reject bad parameters with the JSON path") {
  CHECK_THROWS_WITH_AS(testing::build_tissue({{"builder", "fibrotic_patch"}}, 1),
                       doctest::Contains("tissue.arrangement"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue({{"builder", "in_series"}, {"fm_ratio", -1}}, 1),
                       doctest::Contains("tissue.fm_ratio"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue({{"builder", "interstitial"}, {"fibroblast_radius_um", {4, 1}}}, 1),
                       doctest::Contains("tissue.fibroblast_radius_um"), ManifestError);
  CHECK_THROWS_WITH_AS(testing::build_tissue({{"builder", "interstitial"}, {"colum_spacing_um", 30}}, 1),
                       doctest::Contains("colum_spacing_um"), ManifestError);
}

TEST_CASE("tissue picture (PNG) and VTK files parse") {
  const auto dir = testing::scratch_dir("tissue_files");
  const Tissue t = testing::build_tissue({{"builder", "fibrotic_patch"}, {"arrangement", "in_series"},
                          {"width_mm", 0.6}, {"height_mm", 1.2}, {"patch_width_mm", 0.2},
                          {"patch_height_mm", 0.2}}, 1);
  // PNG by type, and by value with a colour bar.
  PictureOptions options;
  options.height_px = 600;
  write_tissue_png(t, dir / "types.png", nullptr, options);
  std::vector<double> v(t.cell_count());
  for (std::size_t c = 0; c < v.size(); ++c) v[c] = -80 + 100 * t.y_um[c] / 1200;
  options.value_label = "V (mV)";
  write_tissue_png(t, dir / "values.png", &v, options);
  for (const char* name : {"types.png", "values.png"}) {
    const std::string png = testing::read_file(dir / name);
    REQUIRE(png.size() > 1000);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    auto be32 = [&](std::size_t at) {
      return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
             (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
    };
    const auto height = be32(20);
    CHECK(height >= 600);
    CHECK(height <= 700);
    CHECK(be32(16) > 100);  // width
  }
  std::vector<double> bad(3);
  CHECK_THROWS(write_tissue_png(t, dir / "bad.png", &bad));

  write_tissue_vtk(t, dir / "tissue.vtk", {{"V mV", v}});
  std::istringstream in(testing::read_file(dir / "tissue.vtk"));
  std::string line;
  std::getline(in, line);
  CHECK(line == "# vtk DataFile Version 3.0");
  std::getline(in, line);
  std::getline(in, line);
  CHECK(line == "ASCII");
  std::getline(in, line);
  CHECK(line == "DATASET POLYDATA");
  std::string word, type;
  std::size_t n = 0;
  in >> word >> n >> type;
  CHECK(word == "POINTS");
  CHECK(n == t.particles.size());
  const std::string all = testing::read_file(dir / "tissue.vtk");
  CHECK(all.find("POINT_DATA " + std::to_string(n)) != std::string::npos);
  CHECK(all.find("LINES " + std::to_string(t.bonds.size())) != std::string::npos);
  CHECK(all.find("SCALARS V_mV double 1") != std::string::npos);
  CHECK(all.find("SCALARS cell_type int 1") != std::string::npos);
  // Every point line parses as three numbers.
  // (to 9 significant digits, as printf's %.9g)
  double x, y, z;
  std::size_t read = 0, exact = 0;
  for (; read < n && (in >> x >> y >> z); ++read)
    exact += std::abs(x - t.particles[read].x_um) <= 1e-8 * std::abs(t.particles[read].x_um) &&
             std::abs(y - t.particles[read].y_um) <= 1e-8 * std::abs(t.particles[read].y_um) && z == 0;
  CHECK(read == n);
  CHECK(exact == n);
}

// A snapshot's picture (antialias off) fills its disks span by span instead
// of through Cairo's path fill, in the colour bar's colours (steps of 1/200 of
// the range, so that it fits a PNG palette): every particle's centre pixel
// must still show its cell's colour as the antialiased picture (Cairo) draws
// it there, to within half a step (viridis changes by at most 2.6 per unit of
// the range in a channel: 2.6 / 400 x 255 = 1.7 of 255).
TEST_CASE("an unantialiased tissue picture colours each particle's centre as Cairo does") {
  const auto dir = testing::scratch_dir("tissue_picture_fast");
  const Tissue t = testing::build_tissue({{"builder", "in_series"}, {"width_mm", 0.4}, {"height_mm", 0.8}}, 1);
  std::vector<double> v(t.cell_count());
  for (std::size_t c = 0; c < v.size(); ++c) v[c] = -80 + 120 * static_cast<double>(c % 7) / 6;
  PictureOptions options;
  options.height_px = 1200;  // disks of several pixels: the centre pixel is wholly inside
  write_tissue_png(t, dir / "smooth.png", &v, options);
  options.antialias = false;
  write_tissue_png(t, dir / "fast.png", &v, options);
  auto read = [](const std::filesystem::path& file, png_image& image) {
    image = {};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&image, file.c_str()) != 0);
    image.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0);
    return pixels;
  };
  // IHDR's colour type: the snapshot's few colours as a palette (3), the
  // antialiased picture's many as RGB (2).
  CHECK(testing::read_file(dir / "fast.png")[25] == 3);
  CHECK(testing::read_file(dir / "smooth.png")[25] == 2);
  png_image smooth_info, fast_info;
  const auto smooth = read(dir / "smooth.png", smooth_info), fast = read(dir / "fast.png", fast_info);
  REQUIRE(smooth_info.width == fast_info.width);
  REQUIRE(smooth_info.height == fast_info.height);
  // The picture's frame, as write_tissue_png lays it out (margin 20 px, a title-less top).
  const auto b = t.bounds_um();
  const double scale = options.height_px / (b[3] - b[2]);
  std::size_t same = 0, coloured = 0;
  for (const Particle& p : t.particles) {
    const auto x = static_cast<std::size_t>(20 + (p.x_um - b[0]) * scale);
    const auto y = static_cast<std::size_t>(20 + (b[3] - p.y_um) * scale);
    const std::size_t at = 3 * (y * smooth_info.width + x);
    bool equal = true;
    for (int k = 0; k < 3; ++k) equal &= std::abs(int(smooth[at + k]) - int(fast[at + k])) <= 2;
    same += equal;
    coloured += !(fast[at] == 255 && fast[at + 1] == 255 && fast[at + 2] == 255);
  }
  CHECK(coloured == t.particles.size());
  CHECK(same == t.particles.size());
}

TEST_CASE("a tissue that frees its particles keeps its cells, their graph and its bounds") {
  // (A split run's rank other than 0: run/simulation_ranks.cpp.) The bounds
  // come from the particles' edges, not the cells' centres: a region given
  // as fractions of them picks the same cells after as before.
  Tissue t = testing::build_tissue({{"builder", "in_series"}, {"width_mm", 0.5}, {"height_mm", 1.0}}, 3);
  const auto bounds = t.bounds_um();
  const auto edges = t.cell_edges;
  const auto cells = t.cell_count();
  REQUIRE(!t.particles.empty());
  REQUIRE(!t.bonds.empty());
  t.release_particles();
  CHECK(t.particles.empty());
  CHECK(t.bonds.empty());
  CHECK(t.particles.capacity() == 0);
  CHECK(t.cell_count() == cells);
  CHECK(t.cell_edges == edges);
  CHECK(t.bounds_um() == bounds);
  // The centres alone would span less (by a particle's radius at least).
  double x_min = t.x_um[0];
  for (double x : t.x_um) x_min = std::min(x_min, x);
  CHECK(x_min > bounds[0] + kParticleRadius_um - 1e-9);
}
