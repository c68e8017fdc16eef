// Per-cell strain (measure/cell_strain.hpp) against deformations whose
// Green-Lagrange strain is known in closed form: E = (F^T F - I) / 2 of the
// deformation gradient F applied to every particle.
#include <doctest/doctest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "measure/cell_strain.hpp"
#include "support/dem_twitch.hpp"

using namespace fibrodem;

namespace {
// The in-series brick sheet: myocytes of 7 particles and fibroblasts of one,
// each cell with neighbours above, below and to both sides.
Tissue sheet() {
  return testing::build_tissue({{"builder", "in_series"}, {"width_mm", 0.3}, {"height_mm", 0.6}, {"fm_ratio", 0.3}}, 5);
}

std::vector<Particle> moved(const Tissue& t, const std::function<std::array<double, 2>(double, double)>& map) {
  std::vector<Particle> out = t.particles;
  for (auto& p : out) {
    const auto [x, y] = map(p.x_um, p.y_um);
    p.x_um = x;
    p.y_um = y;
  }
  return out;
}

// Whether cell c's neighbours span the plane, from the tissue alone: two of
// its separations from them are not parallel.
bool spanned(const Tissue& t, int c) {
  std::vector<std::array<double, 2>> d;
  for (const auto& [i, j] : t.cell_edges)
    if (i == c || j == c) {
      const int o = i == c ? j : i;
      d.push_back({t.x_um[o] - t.x_um[c], t.y_um[o] - t.y_um[c]});
    }
  for (std::size_t a = 0; a < d.size(); ++a)
    for (std::size_t b = a + 1; b < d.size(); ++b)
      if (std::abs(d[a][0] * d[b][1] - d[a][1] * d[b][0]) > 1e-3 * std::hypot(d[a][0], d[a][1]) * std::hypot(d[b][0], d[b][1]))
        return true;
  return false;
}

// Every cell's fields within 1e-12 of the given ones; NaN exactly in the
// cells whose neighbours do not span the plane.
void check_uniform(const Tissue& t, const CellStrainField& f, double Exx, double Eyy, double Exy) {
  const double stretch = std::sqrt(1 + 2 * Eyy), shear = std::hypot(0.5 * (Exx - Eyy), Exy);
  for (std::size_t c = 0; c < f.E_xx.size(); ++c) {
    CAPTURE(c);
    if (!spanned(t, static_cast<int>(c))) {
      CHECK(std::isnan(f.E_xx[c]));
      continue;
    }
    CHECK(std::abs(f.E_xx[c] - Exx) < 1e-12);
    CHECK(std::abs(f.E_yy[c] - Eyy) < 1e-12);
    CHECK(std::abs(f.E_xy[c] - Exy) < 1e-12);
    CHECK(std::abs(f.fibre_stretch[c] - stretch) < 1e-12);
    CHECK(std::abs(f.max_shear[c] - shear) < 1e-12);
  }
}
}  // namespace

TEST_CASE("cell strain: a sheet at rest has zero strain in every cell, exactly") {
  const Tissue t = sheet();
  CellStrain strain(t);
  REQUIRE(t.cell_count() > 50);
  // Myocytes have neighbours along the fibre and to their sides; a few
  // fibroblast disks in series touch only the cells above and below them in
  // their column (3 of this sheet's 73 cells).
  CHECK(strain.unresolved_cells() > 0);
  CHECK(strain.unresolved_cells() < t.cell_count() / 10);
  strain.compute(t.particles);
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (std::isnan(strain.field().E_xx[c])) CHECK(t.type[c] == CellType::fibroblast);
  check_uniform(t, strain.field(), 0, 0, 0);
  for (double e : strain.field().E_yy) CHECK((e == 0.0 || std::isnan(e)));  // no displacement: no round-off either
}

TEST_CASE("cell strain: a uniform stretch gives its Green-Lagrange strain in every cell") {
  // x scaled by 1.1 and y by 0.95 about (40, -70) um, then moved by (3, 5) um:
  // F = diag(1.1, 0.95), E_xx = (1.1^2 - 1) / 2, E_yy = (0.95^2 - 1) / 2, E_xy = 0.
  const Tissue t = sheet();
  CellStrain strain(t);
  strain.compute(moved(t, [](double x, double y) {
    return std::array<double, 2>{40 + 1.1 * (x - 40) + 3, -70 + 0.95 * (y + 70) + 5};
  }));
  check_uniform(t, strain.field(), (1.1 * 1.1 - 1) / 2, (0.95 * 0.95 - 1) / 2, 0);
}

TEST_CASE("cell strain: a rigid rotation by 30 degrees and a translation give zero strain") {
  const Tissue t = sheet();
  CellStrain strain(t);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  strain.compute(moved(t, [&](double x, double y) {
    return std::array<double, 2>{c * x - s * y + 250, s * x + c * y - 120};
  }));
  check_uniform(t, strain.field(), 0, 0, 0);  // (fibre stretch 1, |F e_y| of a rotation)
}

TEST_CASE("cell strain: simple shear x += 0.2 y gives E_xy = 0.1 and E_yy = 0.02") {
  // F = [1 g; 0 1], F^T F = [1 g; g 1 + g^2]: E_xx = 0, E_xy = g / 2, E_yy = g^2 / 2.
  const double g = 0.2;
  const Tissue t = sheet();
  CellStrain strain(t);
  strain.compute(moved(t, [&](double x, double y) { return std::array<double, 2>{x + g * y, y}; }));
  check_uniform(t, strain.field(), 0, g * g / 2, g / 2);
}

TEST_CASE("cell strain: a cell whose neighbours lie on one line through it, or that has none, is NaN") {
  // Cells 0-1-2 on a line along x, cell 3 above cell 0, cell 4 apart: cell
  // 1's neighbours (0 and 2) lie on a line through it, cells 2 and 3 have
  // one neighbour each, cell 4 none; only cell 0 (neighbours along x and y)
  // is resolved.
  Tissue t;
  for (const auto& [x, y] : {std::array<double, 2>{0, 0}, {20, 0}, {40, 0}, {0, 20}, {100, 100}}) {
    const int c = t.add_cell(CellType::fibroblast, x, y);
    t.add_particle(c, x, y, 10);
  }
  t.add_bond(0, 1);
  t.add_bond(1, 2);
  t.add_bond(0, 3);
  t.finalise();
  CellStrain strain(t);
  CHECK(strain.unresolved_cells() == 4);
  const auto& f = strain.compute(moved(t, [](double x, double y) { return std::array<double, 2>{1.1 * x, y}; }));
  CHECK(f.E_xx[0] == doctest::Approx((1.1 * 1.1 - 1) / 2).epsilon(1e-12));
  for (int c : {1, 2, 3, 4}) {
    CAPTURE(c);
    CHECK(std::isnan(f.E_xx[c]));
    CHECK(std::isnan(f.E_yy[c]));
    CHECK(std::isnan(f.E_xy[c]));
    CHECK(std::isnan(f.fibre_stretch[c]));
    CHECK(std::isnan(f.max_shear[c]));
  }
  // A one-cell-wide strand: every cell's neighbours lie along it.
  const Tissue strand = testing::build_tissue({{"builder", "strand"}, {"type", "fibroblast"}, {"cells", 5}});
  CHECK(CellStrain(strand).unresolved_cells() == 5);
}

TEST_CASE("cell strain: a twitching DEM sheet's field is the same bits on 1 and 2 threads") {
  // The small in-series sheet of the DEM schemes' checks at its twitch's
  // shortest (40 ms, myocytes at 0.9 of their length).
  const Tissue t = test::small_in_series_tissue();
  DemSolver dem(t, DemSpec{});
  std::vector<double> ratio(t.cell_count(), 1.0);
  while (dem.time_ms() < 40) test::twitch_step(t, dem, ratio);
  CellStrain strain(t);
  const int threads_before = omp_get_max_threads();
  std::vector<CellStrainField> fields;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    fields.push_back(strain.compute(dem.particles()));
  }
  omp_set_num_threads(threads_before);
  const auto same_bits = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  CHECK(same_bits(fields[0].E_xx, fields[1].E_xx));
  CHECK(same_bits(fields[0].E_yy, fields[1].E_yy));
  CHECK(same_bits(fields[0].E_xy, fields[1].E_xy));
  CHECK(same_bits(fields[0].fibre_stretch, fields[1].fibre_stretch));
  // And the field is the twitch's: the tissue shortened along the fibres
  // (its fitted strain eps_yy is negative), and so did the mean cell.
  double mean_E_yy = 0;
  for (double e : fields[0].E_yy)
    if (!std::isnan(e)) mean_E_yy += e / static_cast<double>(t.cell_count() - strain.unresolved_cells());
  CAPTURE(mean_E_yy);
  CAPTURE(dem.strain()[1]);
  CHECK(dem.strain()[1] < -0.02);
  CHECK(mean_E_yy < -0.02);
}
