// Per-cell strain in a run's outputs: the stretch at each phase singularity
// (phase_singularities.csv), the re-entry samples' strain interpolated
// within a step (run/strain_fields.hpp), and the snapshots' fields and
// pictures of a contracting sheet, the same bits on 1 and 2 threads.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "measure/reentry.hpp"
#include "run/strain_fields.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

namespace {
constexpr double kPi = std::numbers::pi;

// n x n cells 100 um apart, each joined to the cells beside and above it.
Tissue grid(int n) {
  Tissue t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int c = t.add_cell(CellType::myocyte, i * 100.0, j * 100.0);
      t.add_particle(c, i * 100.0, j * 100.0, 12.5);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) t.add_bond(j * n + i, j * n + i + 1);
      if (j + 1 < n) t.add_bond(j * n + i, (j + 1) * n + i);
    }
  t.finalise();
  return t;
}

// A solver whose particles the test places; nothing else of it is used.
class PlacedParticles : public MechanicsSolver {
 public:
  explicit PlacedParticles(std::vector<Particle> p) : particles_(std::move(p)) {}
  std::vector<Particle> particles_;
  double stable_step_ms() const override { return 1; }
  double step_ms() const override { return 1; }
  void set_cell_length_ratios(const std::vector<double>&) override {}
  void step(double) override {}
  std::array<double, 3> strain() const override { return {0, 0, 0}; }
  std::string report() const override { return {}; }
  void save(CheckpointFields&) const override {}
  void load(const CheckpointFields&) override {}
  const std::vector<Particle>& particles() const override { return particles_; }
  Motion fastest_motion() const override { return {}; }
};
}  // namespace

TEST_CASE("the stretch at a phase singularity is its triangle's cells' mean, the last column with mechanics") {
  // The spiral of test_reentry.cpp (V* + 40 cos(omega t - theta) about
  // (x0, y0), one PS of charge -1 at the triangle around (x0, y0)) over a
  // fibre stretch linear in x, 1 + 1e-5 x / um: the mean of a triangle's
  // three cells is the value at its centroid, where the PS is placed, so
  // each row's stretch is 1 + 1e-5 x_mm 1000 (to float's 1e-7).
  const Tissue t = grid(21);
  const double x0 = 1033, y0 = 987, period = 200, omega = 2 * kPi / period, V_star = -50;
  const ReentrySettings s{.every_ms = 5, .from_ms = 0, .tau_ms = period / 4, .V_star_mV = V_star, .link_mm = 1};
  VoltageFrames frames(t.cell_count());
  StretchFrames stretch(t.cell_count());
  for (double time = 0; time <= 400 + 1e-9; time += 5) {
    std::vector<double> V(t.cell_count()), lambda(t.cell_count());
    for (std::size_t c = 0; c < V.size(); ++c) {
      V[c] = V_star + 40 * std::cos(omega * time - std::atan2(t.y_um[c] - y0, t.x_um[c] - x0));
      lambda[c] = time < 400 ? 1 + 1e-5 * t.x_um[c] : std::nan("");  // the last frame: no cell has a strain
    }
    frames.add(time, V);
    stretch.add(time, lambda);
  }
  const auto dir = testing::scratch_dir("ps_stretch");
  analyse_reentry(t, frames, s, {0}, {}, dir, nullptr, &stretch);
  const auto rows = testing::csv_rows(dir / "phase_singularities.csv");
  REQUIRE(rows.size() == 1 + 71);  // a PS in each frame from 50 to 400 ms
  CHECK(rows[0] == std::vector<std::string>{"t_ms", "id", "x_mm", "y_mm", "chirality", "stretch"});
  for (std::size_t k = 1; k + 1 < rows.size(); ++k) {
    CAPTURE(k);
    CHECK(std::stod(rows[k][5]) == doctest::Approx(1 + 1e-5 * 1000 * std::stod(rows[k][2])).epsilon(1e-6));
  }
  CHECK(rows.back()[5] == "nan");
  // Without the stretch, the file is the EP-only one.
  analyse_reentry(t, frames, s, {0}, {}, dir);
  CHECK(testing::csv_rows(dir / "phase_singularities.csv")[0].size() == 5);
  // Stretch frames at other times than V's are a programming error, named.
  StretchFrames fewer(t.cell_count());
  fewer.add(0, std::vector<double>(t.cell_count(), 1.0));
  CHECK_THROWS_WITH_AS(analyse_reentry(t, frames, s, {0}, {}, {}, nullptr, &fewer),
                       doctest::Contains("sampled at 1 times, V at 81"), std::invalid_argument);
}

TEST_CASE("a re-entry sample inside a step takes the strain of the cells' positions interpolated to its time") {
  // Particles at rest at the step's start, y stretched by 1.1 at its end: a
  // sample a quarter into the step sees y stretched by 1.025, a fibre
  // stretch of exactly that in every cell (float: to 1e-7); one at the
  // step's end the full 1.1.
  const Tissue t = grid(5);
  StrainFields fields(t);
  PlacedParticles dem(t.particles);
  fields.sample_now(0, dem);
  fields.due(2.5, 0.25, dem);
  fields.due(10, 1.0, dem);
  for (auto& p : dem.particles_) p.y_um *= 1.1;
  fields.complete(dem);
  const StretchFrames& frames = fields.stretch_frames();
  REQUIRE(frames.count() == 3);
  CHECK(frames.t_ms == std::vector<double>{0, 2.5, 10});
  for (std::size_t c = 0; c < t.cell_count(); ++c) {
    CAPTURE(c);
    CHECK(frames.frame(0)[c] == 1.0f);
    CHECK(frames.frame(1)[c] == doctest::Approx(1.025).epsilon(1e-7));
    CHECK(frames.frame(2)[c] == doctest::Approx(1.1).epsilon(1e-7));
  }
  fields.complete(dem);  // nothing due: no frame
  CHECK(frames.count() == 3);
}

TEST_CASE("a contracting sheet's snapshots carry each cell's strain, the same bits on 1 and 2 threads" *
          doctest::test_suite("threads")) {
  // By 80 ms the sheet has contracted (tissue strain eps_yy -0.04, its cells' E_yy -0.027 to -0.040).
  json m = json::parse(R"({
    "fibrodem": 1, "name": "em_strain", "seed": 3, "duration_ms": 80,
    "effects": ["electrophysiology", "coupling", "mechanics"],
    "tissue": {"builder": "in_series", "width_mm": 0.2, "height_mm": 0.4, "fm_ratio": 0.2},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 0.3},
    "stimulus": [{"target": "myocyte", "start_ms": 1, "duration_ms": 2, "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"snapshots": {"every_ms": 40, "from_ms": 40, "png": false, "strain": true},
               "reentry": {"every_ms": 1, "tau_ms": 5}}
  })");
  std::string first;
  for (int threads : {1, 2}) {
    CAPTURE(threads);
    m["solver"]["threads"] = threads;
    const auto dir = testing::scratch_dir("em_strain_" + std::to_string(threads));
    m["output"]["dir"] = dir.string();
    Simulation(parse_scene(m)).run();
    CHECK(std::filesystem::exists(dir / "strain_00080.000_ms.png"));
    const std::string vtk = testing::read_file(dir / "snapshot_00080.000_ms.vtk");
    for (const char* field : {"E_xx", "E_yy", "E_xy", "fibre_stretch", "max_shear"})
      CHECK(vtk.find(std::string("SCALARS ") + field + " double") != std::string::npos);
    CHECK(testing::csv_rows(dir / "phase_singularities.csv")[0].back() == "stretch");
    if (first.empty()) first = vtk + testing::read_file(dir / "snapshot_00040.000_ms.vtk");
    else CHECK(vtk + testing::read_file(dir / "snapshot_00040.000_ms.vtk") == first);
  }
  // Without mechanics: neither the fields nor the column, and the strain picture is refused.
  m["effects"] = {"electrophysiology", "coupling"};
  m["solver"]["threads"] = 1;
  m["output"]["snapshots"].erase("strain");
  const auto dir = testing::scratch_dir("em_strain_ep");
  m["output"]["dir"] = dir.string();
  Simulation(parse_scene(m)).run();
  CHECK(testing::read_file(dir / "snapshot_00080.000_ms.vtk").find("E_xx") == std::string::npos);
  CHECK(testing::csv_rows(dir / "phase_singularities.csv")[0].back() == "chirality");
  m["output"]["snapshots"]["strain"] = true;
  m["output"].erase("dir");
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(m)), doctest::Contains("output.snapshots.strain"), ManifestError);
}

TEST_CASE("output.snapshots.strain without listed effects builds mechanics, and says why") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "strain_plan", "duration_ms": 1,
    "tissue": {"builder": "in_series", "width_mm": 0.1, "height_mm": 0.3, "fm_ratio": 0.2},
    "cells": {"myocyte": {"model": "colman", "myofilament": "rice"}, "fibroblast": {"model": "maleckar_active2"}},
    "output": {"snapshots": {"every_ms": 1, "strain": true}}
  })");
  const ProcessPlan plan = Simulation(parse_scene(m)).processes();
  REQUIRE(plan.has("mechanics"));
  CHECK(plan.built[1].reason.find("output.snapshots.strain") != std::string::npos);
}
