// DEM tissue mechanics (core/mechanics): the manifest's `mechanics` spec, the
// clumps' area rules, a bonded pair against the analytic oscillator, a
// collision of unbonded disks against the analytic restitution, energy
// without damping, zero strain under rigid motion, the imposed strain of a
// uniform contraction, the stable step refused above, a bounded contraction
// cycle with the seed paper's Table 1, loose interstitial tissue whose
// bodies meet through contact detection instead of passing through, and the
// same bits on one thread and on two.
#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "mechanics/clump_geometry.hpp"
#include "mechanics/dem_solver.hpp"
#include "support/dem_probe.hpp"
#include "support/scenes.hpp"
#include "tissue/builders/column_tissue.hpp"

using namespace fibrodem;
using fibrodem::test::max_displacement_um;

namespace {

Tissue small_in_series(double fm_ratio) {
  return testing::build_tissue(
      {{"builder", "in_series"}, {"width_mm", 0.2}, {"height_mm", 0.6}, {"fm_ratio", fm_ratio}}, 3);
}

// Two round fibroblasts touching along x, bonded.
Tissue bonded_pair() {
  Tissue t;
  add_round_fibroblast(t, 0, 0);
  add_round_fibroblast(t, 2 * kParticleRadius_um, 0);
  t.add_bond(0, 1);
  t.finalise();
  return t;
}

std::vector<double> ratios(const Tissue& t, double lambda) {
  std::vector<double> r(t.cell_count(), 1.0);
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) r[c] = lambda;
  return r;
}

// Ramps every myocyte to lambda over `ramp` steps, then holds it for `hold` steps.
// Steps of the solver's own (automatic) step: new contacts may change it.
void contract(DemSolver& dem, const Tissue& t, double lambda, int ramp, int hold) {
  for (int k = 1; k <= ramp + hold; ++k) {
    const double f = k >= ramp ? 1.0 : 0.5 * (1 - std::cos(M_PI * k / ramp));
    dem.set_cell_length_ratios(ratios(t, 1 + (lambda - 1) * f));
    dem.step(dem.step_ms());
  }
}

// Myocyte pitch along a fibre (end particles' centres to the next cell's) at lambda.
double myocyte_pitch_um(const DemSpec& s, double lambda) {
  const ClumpShape c = contracted_shape(s.area_rule, s.length_mode, kMyocyteParticles, kParticleRadius_um,
                                        kParticleSpacing_um, lambda);
  return (kMyocyteParticles - 1) * c.s + 2 * c.r;
}

}  // namespace

TEST_CASE("dem: the mechanics spec defaults to Table 1 and names the path of a bad value") {
  const json empty = json::object();
  JsonReader r(empty, "mechanics");
  const DemSpec s = read_dem_spec(r);
  CHECK(s.solver == "dem");
  CHECK(s.contact_law == "linear_bond");
  CHECK(s.kn_N_per_m == 26.0);
  CHECK(s.ks_N_per_m == 0.26);
  CHECK(s.damping_ratio_normal == 0.1);
  CHECK(s.damping_ratio_shear == 0.1);
  CHECK(s.tensile_strength_N == 1e200);
  CHECK(s.shear_strength_N == 1e200);
  CHECK(s.density_kg_per_m3 == 1053.0);
  CHECK(s.area_rule == AreaRule::union_area);
  CHECK_FALSE(s.fibroblasts_fixed);
  CHECK(s.contact_detection);       // PFC detects new contacts
  CHECK(s.local_damping == 0.0);    // Table 1 lists dashpots only
  CHECK(s.bond_radius_multiplier == 1.0);  // PFC's pb_rmul default

  const json set = {{"kn_N_per_m", 39}, {"area_rule", "rectangle"}, {"fibroblasts_fixed", true},
                    {"fibroblast_stiffness_factor", 1.5}, {"strain_bodies", "bodies"}};
  JsonReader r2(set, "mechanics");
  const DemSpec s2 = read_dem_spec(r2);
  r2.finish();
  CHECK(s2.kn_N_per_m == 39.0);
  CHECK(s2.area_rule == AreaRule::rectangle);
  CHECK(s2.fibroblasts_fixed);
  CHECK(s2.fibroblast_stiffness_factor == 1.5);
  CHECK(s2.strain_bodies == StrainBodies::bodies);

  for (const json& bad : {json{{"kn_N_per_m", -1}}, json{{"area_rule", "square"}},
                          json{{"contact_law", "hertz"}}, json{{"safety_factor", 2}},
                          json{{"local_damping", 1.5}}, json{{"contact_skin_um", 0}},
                          json{{"contact_detection", "yes"}}, json{{"bond_radius_multiplier", -1}}}) {
    JsonReader rb(bad, "mechanics");
    const std::string key = bad.begin().key();
    CHECK_THROWS_WITH_AS(read_dem_spec(rb), doctest::Contains(("mechanics." + key).c_str()), ManifestError);
  }
}

TEST_CASE("dem: contracting clumps keep their area by each rule") {
  const int n = kMyocyteParticles;
  const double r0 = kParticleRadius_um, s0 = kParticleSpacing_um;
  // docs/reference/references.md#dem-clumps: union of the seed's clump 2790.8 um^2; disk 490.9, lens 107.6.
  CHECK(union_area(n, r0, s0) == doctest::Approx(2790.8).epsilon(1e-5));
  CHECK(union_area(1, r0, s0) == doctest::Approx(490.87).epsilon(1e-4));
  CHECK(2 * union_area(1, r0, s0) - union_area(2, r0, s0) == doctest::Approx(107.6).epsilon(1e-3));
  // docs/reference/references.md#dem-contraction-rule table (spacing s0 lambda): r_A, r_B, r_C.
  const double table[][4] = {{0.95, 12.834, 12.963, 13.158},
                             {0.90, 13.208, 13.456, 13.889},
                             {0.85, 13.627, 13.981, 14.706},
                             {0.80, 14.090, 14.541, 15.625}};
  for (const auto& row : table) {
    CAPTURE(row[0]);
    const AreaRule rules[] = {AreaRule::union_area, AreaRule::capsule, AreaRule::rectangle};
    for (int k = 0; k < 3; ++k) {
      const ClumpShape c = contracted_shape(rules[k], LengthMode::spacing, n, r0, s0, row[0]);
      CHECK(c.s == doctest::Approx(s0 * row[0]));
      CHECK(c.r == doctest::Approx(row[k + 1]).epsilon(1e-4));
    }
  }
  // The kept area, in both length modes, shortening and stretching.
  for (AreaRule rule : {AreaRule::union_area, AreaRule::capsule, AreaRule::rectangle})
    for (LengthMode mode : {LengthMode::spacing, LengthMode::total})
      for (double l : {0.82, 0.9, 0.97, 1.0, 1.05, 1.15}) {
        CAPTURE(l);
        CAPTURE(area_rule_name(rule));
        CAPTURE(length_mode_name(mode));
        const ClumpShape c = contracted_shape(rule, mode, n, r0, s0, l);
        CHECK(rule_area(rule, n, c.r, c.s) == doctest::Approx(rule_area(rule, n, r0, s0)).epsilon(1e-12));
        if (mode == LengthMode::total)
          CHECK((n - 1) * c.s + 2 * c.r == doctest::Approx(l * kMyocyteLength_um).epsilon(1e-12));
      }
  // Exact also where disks k and k+2 overlap (s < r): against a fine grid.
  {
    const double r = 10, s = 6;
    const int cells = 2000;
    const double x0 = -3 * s - r, w = 6 * s + 2 * r, hgrid = w / cells;
    double area = 0;
    for (int i = 0; i < cells; ++i)
      for (int j = 0; j < cells / 4; ++j) {
        const double x = x0 + (i + 0.5) * hgrid, y = -r + (j + 0.5) * (2 * r / (cells / 4));
        bool in = false;
        for (int k = 0; k < 7 && !in; ++k) in = std::hypot(x - (k - 3) * s, y) <= r;
        area += in ? hgrid * (2 * r / (cells / 4)) : 0;
      }
    CHECK(union_area(7, r, s) == doctest::Approx(area).epsilon(2e-3));
  }
  // Polar moment: a disk, and disjoint disks (parallel axes).
  CHECK(union_polar_moment(1, 2.0, 0) == doctest::Approx(M_PI * 16 / 2).epsilon(1e-9));
  // 7 disks r 2 at s 4 (touching): 7 pi r^4 / 2 + pi r^2 sum a^2, sum a^2 = 16 * 28.
  CHECK(union_polar_moment(7, 2.0, 4.0) == doctest::Approx(7 * M_PI * 8 + 4 * M_PI * 448).epsilon(1e-9));
  // The solver's clump: mass and shape.
  Tissue t;
  add_myocyte(t, 0, 0, 0.3);
  t.finalise();
  // The default length mode (`total`, the seed's words) makes the end-to-end
  // length lambda L0; `spacing` makes s = lambda s0 (docs/reference/references.md#dem-contraction-rule).
  {
    DemSolver total(t, DemSpec{});
    total.set_cell_length_ratios({0.9});
    total.step(0.001);
    const ClumpShape c = total.cell_shape_um(0);
    CHECK((n - 1) * c.s + 2 * c.r == doctest::Approx(0.9 * ((n - 1) * s0 + 2 * r0)).epsilon(1e-9));
    CHECK(union_area(n, c.r, c.s) == doctest::Approx(union_area(n, r0, s0)).epsilon(1e-12));
  }
  DemSpec spacing;
  spacing.length_mode = LengthMode::spacing;
  DemSolver dem(t, spacing);
  CHECK(dem.body(0).mass_kg == doctest::Approx(1053 * 2790.8e-12).epsilon(1e-5));  // 2.94e-6 kg
  dem.set_cell_length_ratios({0.9});
  dem.step(0.001);
  const ClumpShape c = dem.cell_shape_um(0);
  CHECK(union_area(n, c.r, c.s) == doctest::Approx(union_area(n, r0, s0)).epsilon(1e-12));
  CHECK(c.r == doctest::Approx(13.208).epsilon(1e-4));
  CHECK_THROWS_AS(dem.set_cell_length_ratios({0.4}), std::invalid_argument);
  CHECK_THROWS_AS(dem.set_cell_length_ratios({0.9, 0.9}), std::invalid_argument);
  dem.step(0.001);
  CHECK(dem.cell_shape_um(0).r == c.r);  // unchanged by the refused ratios
  // An isolated contracting clump does not move.
  CHECK(dem.body(0).vx_m_per_s == 0.0);
  CHECK(dem.body(0).omega_rad_per_s == 0.0);
  CHECK(dem.strain()[1] < 0);  // its particles close up along the axis
}

TEST_CASE("dem: a shape solve started from the last step's radius finds the cold start's root") {
  // A run solves each clump's shape from its radius a DEM step before (length
  // ratio ~1e-4 away) and stops once a Newton step is below 1e-9 r; the root
  // must be the one a solve from the rest radius finds, to rounding (4 ulp),
  // and keep the area as well.
  const int n = kMyocyteParticles;
  const double r0 = kParticleRadius_um, s0 = kParticleSpacing_um;
  for (AreaRule rule : {AreaRule::union_area, AreaRule::capsule, AreaRule::rectangle})
    for (LengthMode mode : {LengthMode::spacing, LengthMode::total})
      for (double l : {0.82, 0.9, 0.97, 0.9999, 1.05}) {
        CAPTURE(l);
        CAPTURE(area_rule_name(rule));
        CAPTURE(length_mode_name(mode));
        const ClumpShape cold = contracted_shape(rule, mode, n, r0, s0, l);
        const double previous_r = contracted_shape(rule, mode, n, r0, s0, l + 1e-4).r;
        const ClumpShape warm = contracted_shape(rule, mode, n, r0, s0, l, previous_r);
        CHECK(std::abs(warm.r - cold.r) <= 4 * std::numeric_limits<double>::epsilon() * cold.r);
        CHECK(rule_area(rule, n, warm.r, warm.s) == doctest::Approx(rule_area(rule, n, r0, s0)).epsilon(1e-14));
      }
}

TEST_CASE("dem: one bad length ratio among many is named by its cell and changes no cell's shape") {
  const Tissue t = testing::build_tissue({{"builder", "in_series"}, {"width_mm", 0.4}, {"height_mm", 1.0}}, 3);
  DemSolver dem(t, DemSpec{});
  std::vector<double> r = ratios(t, 0.9);
  std::size_t last_myocyte = 0;
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) last_myocyte = c;
  REQUIRE(last_myocyte > 64);  // past the first chunk a thread takes
  r[last_myocyte] = 1.7;
  const std::string named = "cell " + std::to_string(last_myocyte) + ": length ratio 1.7";
  CHECK_THROWS_WITH_AS(dem.set_cell_length_ratios(r), doctest::Contains(named.c_str()), std::invalid_argument);
  dem.step(dem.step_ms());
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) {
      CAPTURE(c);
      CHECK(dem.cell_shape_um(c).r == kParticleRadius_um);  // every cell still at rest
    }
}

TEST_CASE("dem: two bonded disks oscillate at the analytic period and decay by the damping ratio") {
  const Tissue t = bonded_pair();
  for (double beta : {0.0, 0.1}) {
    CAPTURE(beta);
    DemSpec spec;
    spec.damping_ratio_normal = spec.damping_ratio_shear = beta;
    DemSolver dem(t, spec);
    const double m = dem.body(0).mass_kg;
    CHECK(m == doctest::Approx(1053 * M_PI * 12.5e-6 * 12.5e-6).epsilon(1e-12));  // 5.17e-7 kg
    const double m_eff = m / 2, kn = 26;
    const double period_ms = 2 * M_PI * std::sqrt(m_eff / kn) * 1e3 / std::sqrt(1 - beta * beta);
    const double dt = period_ms / 2000;
    REQUIRE(dt < dem.stable_step_ms());
    dem.set_body_velocity(0, -1e-3, 0, 0);
    dem.set_body_velocity(1, 1e-3, 0, 0);
    // Opening x(t) = gap - ref: zero crossings and peaks.
    std::vector<double> crossings, peaks;
    double prev = 0, prev2 = 0;
    for (int k = 1; k <= 8000; ++k) {
      dem.step(dt);
      const auto& p = dem.particles();
      const double x = (p[1].x_um - p[0].x_um) - 25.0;
      if (k > 1 && ((prev > 0) != (x > 0))) crossings.push_back((k - 1 + prev / (prev - x)) * dt);
      if (k > 2 && prev > prev2 && prev >= x && prev > 0) peaks.push_back(prev);
      prev2 = prev;
      prev = x;
    }
    REQUIRE(crossings.size() >= 6);
    const double measured = 2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
    CHECK(measured == doctest::Approx(period_ms).epsilon(1e-4));
    REQUIRE(peaks.size() >= 3);
    const double decrement = std::log(peaks[0] / peaks[1]);
    CHECK(decrement == doctest::Approx(2 * M_PI * beta / std::sqrt(1 - beta * beta)).epsilon(5e-3));
    if (beta == 0) CHECK(peaks.back() == doctest::Approx(peaks.front()).epsilon(1e-5));
  }
}

TEST_CASE("dem: a parallel bond resists bending at kb = kn R^2/3, the contact bond is a hinge") {
  // Two bonded disks counter-spinning (+w, -w): their surfaces move together
  // at the contact, so no force acts. With linear_parallel_bond the bond's
  // moment M = -kb (theta_q - theta_p) gives each disk I theta'' = -2 kb theta:
  // a period 2 pi sqrt(I / (2 kb)), kb = kn R^2 / 3, R = 12.5 um; with
  // linear_bond the spins never change.
  const Tissue t = bonded_pair();
  for (const std::string law : {"linear_bond", "linear_parallel_bond"}) {
    CAPTURE(law);
    DemSpec spec;
    spec.contact_law = law;
    spec.damping_ratio_normal = spec.damping_ratio_shear = 0;
    DemSolver dem(t, spec);
    const double I = dem.body(0).inertia_kg_m2, R = 12.5e-6;
    const double kb = 26 * R * R / 3;
    const double period_ms = 2 * M_PI * std::sqrt(I / (2 * kb)) * 1e3;
    const double dt = std::min(dem.stable_step_ms(), period_ms / 500);
    dem.set_body_velocity(0, 0, 0, 1.0);
    dem.set_body_velocity(1, 0, 0, -1.0);
    std::vector<double> crossings;
    double prev = 1.0, w_min = 1.0;
    for (int k = 1; k <= 3000; ++k) {
      dem.step(dt);
      const double w = dem.body(0).omega_rad_per_s;
      if ((prev > 0) != (w > 0)) crossings.push_back((k - 1 + prev / (prev - w)) * dt);
      prev = w;
      w_min = std::min(w_min, w);
    }
    if (law == "linear_bond") {
      CHECK(w_min == doctest::Approx(1.0).epsilon(1e-9));
    } else {
      REQUIRE(crossings.size() >= 4);
      const double measured = 2 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
      CHECK(measured == doctest::Approx(period_ms).epsilon(1e-3));
      CHECK(dem.bonds().kb[0] == doctest::Approx(kb).epsilon(1e-12));
    }
  }
}

TEST_CASE("dem: unbonded disks collide as a linear spring-dashpot, and pass through without detection") {
  // Two free round fibroblasts 5 um apart (no bond), closing at 2 mm/s: the
  // contact found by detection is PFC's linear model. Analytic (a damped
  // half-oscillation from overlap 0 back to overlap 0): contact time
  // pi / (w_n sqrt(1 - beta^2)), w_n = sqrt(kn / m_eff); restitution
  // e = exp(-pi beta / sqrt(1 - beta^2)) (0.7292 at Table 1's beta 0.1).
  Tissue t;
  add_round_fibroblast(t, 0, 0);
  add_round_fibroblast(t, 2 * kParticleRadius_um + 5, 0);
  t.finalise();
  REQUIRE(t.bonds.empty());
  for (double beta : {0.0, 0.1}) {
    CAPTURE(beta);
    DemSpec spec;
    spec.damping_ratio_normal = spec.damping_ratio_shear = beta;
    DemSolver dem(t, spec);
    const double m_eff = dem.body(0).mass_kg / 2, kn = 26;
    const double contact_ms = M_PI / (std::sqrt(kn / m_eff) * std::sqrt(1 - beta * beta)) * 1e3;
    const double dt = contact_ms / 1000;
    dem.set_body_velocity(0, 1e-3, 0, 0);
    dem.set_body_velocity(1, -1e-3, 0, 0);
    double first = -1, last = -1;
    for (int k = 1; k <= 12000; ++k) {  // 2.5 ms to close the gap, then the contact
      dem.step(dt);
      const auto& p = dem.particles();
      if (p[1].x_um - p[0].x_um < 2 * kParticleRadius_um) {
        if (first < 0) first = k * dt;
        last = k * dt;
      }
    }
    REQUIRE(first > 0);
    CHECK(dem.contact_list_builds() >= 2);  // the pair was listed only once the disks came within the skin
    CHECK(last - first == doctest::Approx(contact_ms).epsilon(3e-3));
    const double e = (dem.body(1).vx_m_per_s - dem.body(0).vx_m_per_s) / 2e-3;
    CHECK(e == doctest::Approx(std::exp(-M_PI * beta / std::sqrt(1 - beta * beta))).epsilon(2e-3));
    CHECK(dem.touching_contacts() == 0);  // parted
    // Momentum is conserved whatever the damping.
    CHECK(dem.body(0).vx_m_per_s + dem.body(1).vx_m_per_s == doctest::Approx(0).epsilon(1e-15));
  }
  DemSpec spec;
  spec.contact_detection = false;
  DemSolver ghost(t, spec);
  ghost.set_body_velocity(0, 1e-3, 0, 0);
  ghost.set_body_velocity(1, -1e-3, 0, 0);
  for (int k = 0; k < 2000; ++k) ghost.step(0.01);  // 20 ms: 40 um each
  CHECK(ghost.particles()[0].x_um > ghost.particles()[1].x_um);  // passed through
}

TEST_CASE("dem: without damping a tissue's energy is conserved to the scheme's order") {
  const Tissue t = small_in_series(0.4);
  for (const std::string law : {"linear_bond", "linear_parallel_bond"}) {
    CAPTURE(law);
    DemSpec spec;
    spec.contact_law = law;
    spec.damping_ratio_normal = spec.damping_ratio_shear = 0;
    double drift[2];
    for (int refine = 0; refine < 2; ++refine) {
      DemSolver dem(t, spec);
      std::uint64_t state = 12345;
      auto rnd = [&state] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
      };
      for (std::size_t b = 0; b < dem.body_count(); ++b)
        dem.set_body_velocity(b, 1e-3 * rnd(), 1e-3 * rnd(), 10 * rnd());
      const double e0 = dem.kinetic_energy_J() + dem.elastic_energy_J();
      const double dt = dem.stable_step_ms() / (4 << refine);
      double worst = 0;
      for (int k = 0; k < (1000 << refine); ++k) {
        dem.step(dt);
        worst = std::max(worst, std::abs(dem.kinetic_energy_J() + dem.elastic_energy_J() - e0) / e0);
      }
      drift[refine] = worst;
    }
    MESSAGE(law, ": relative energy error ", drift[0], " at dt_stable/4, ", drift[1], " at dt_stable/8");
    CHECK(drift[0] < 5e-3);
    CHECK(drift[1] < drift[0] / 3);  // second order
  }
}

TEST_CASE("dem: a rigid translation or rotation of a tissue gives no strain") {
  const Tissue t = small_in_series(0.4);
  for (StrainBodies bodies : {StrainBodies::particles, StrainBodies::bodies}) {
    CAPTURE(bodies == StrainBodies::bodies);
    DemSpec spec;
    spec.strain_bodies = bodies;
    auto largest = [](const DemSolver& dem) {
      const auto e = dem.strain();
      return std::max({std::abs(e[0]), std::abs(e[1]), std::abs(e[2])});
    };
    // A translation stays exact.
    {
      DemSolver dem(t, spec);
      for (std::size_t b = 0; b < dem.body_count(); ++b) dem.set_body_velocity(b, 0.01, -0.02, 0);
      for (int k = 0; k < 500; ++k) dem.step(dem.stable_step_ms());
      CHECK(largest(dem) < 1e-12);
    }
    // A spinning clump on its own: its particles turn exactly about its centroid.
    {
      Tissue one;
      add_myocyte(one, 10, 20, 0.2);
      one.finalise();
      DemSolver dem(one, spec);
      dem.set_body_velocity(0, 0.003, 0.001, 50);
      for (int k = 0; k < 1000; ++k) dem.step(0.01);
      CHECK(dem.body(0).theta_rad == doctest::Approx(0.2 + 50 * 10e-3));
      if (bodies == StrainBodies::particles) CHECK(largest(dem) < 1e-12);
    }
    // A tissue set spinning: bodies move on straight lines between steps, so
    // they fly apart (a true strain, (w t)^2 / 2 unrestrained) until the
    // bonds take up the centripetal force.
    {
      DemSolver dem(t, spec);
      const double w = 2.0, cx = 1e-4, cy = 3e-4;
      for (std::size_t b = 0; b < dem.body_count(); ++b) {
        const auto s = dem.body(b);
        dem.set_body_velocity(b, -w * (s.y_m - cy), w * (s.x_m - cx), w);
      }
      const double dt = dem.stable_step_ms();
      for (int k = 0; k < 500; ++k) dem.step(dt);
      const double wt = w * dem.time_ms() * 1e-3;
      CHECK(dem.body(0).theta_rad == doctest::Approx(wt).epsilon(1e-3));
      CHECK(largest(dem) < 0.1 * wt * wt / 2);
      MESSAGE("tissue spun 0.04 rad: largest strain ", largest(dem), ", unrestrained ", wt * wt / 2);
    }
  }
}

TEST_CASE("dem: a uniform contraction gives the imposed strain along the fibre") {
  // A strand of myocytes end to end: at rest again, each cell's pitch is
  // (N-1)s + 2r (the end particles' bond back at its reference gap), so the
  // fibre strain is ln(pitch(lambda) / 125 um) -- ln(lambda) in length mode
  // `total`, less in `spacing` (the radii grow); the strand has no lateral
  // spread, so no lateral strain.
  const Tissue strand = testing::build_tissue({{"builder", "strand"}, {"type", "myocyte"}, {"cells", 5}});
  for (AreaRule rule : {AreaRule::union_area, AreaRule::capsule, AreaRule::rectangle})
    for (LengthMode mode : {LengthMode::spacing, LengthMode::total}) {
      for (StrainBodies bodies : {StrainBodies::bodies, StrainBodies::particles}) {
        CAPTURE(std::string(area_rule_name(rule)));
        CAPTURE(std::string(length_mode_name(mode)));
        CAPTURE(bodies == StrainBodies::bodies);
        DemSpec spec;
        spec.area_rule = rule;
        spec.length_mode = mode;
        spec.strain_bodies = bodies;
        DemSolver dem(strand, spec);
        contract(dem, strand, 0.9, 100, 600);
        const double expected = std::log(myocyte_pitch_um(spec, 0.9) / kMyocyteLength_um);
        if (mode == LengthMode::total) CHECK(expected == doctest::Approx(std::log(0.9)));
        if (bodies == StrainBodies::bodies) {
          CHECK(dem.strain()[1] == doctest::Approx(expected).epsilon(1e-4));
        } else {
          // Particles also move within their clump, at ln(s/s0): the fit mixes
          // that in with the weight of the particles' spread within a clump.
          const double s = contracted_shape(rule, mode, kMyocyteParticles, kParticleRadius_um,
                                            kParticleSpacing_um, 0.9).s;
          const double within = 4 * kParticleSpacing_um * kParticleSpacing_um;  // var of (k-3) s0
          const double between = 125.0 * 125.0 * (25 - 1) / 12;                 // 5 cells
          const double w = within / (within + between);
          CHECK(dem.strain()[1] ==
                doctest::Approx(expected + w * (std::log(s / kParticleSpacing_um) - expected)).epsilon(2e-3));
        }
        CHECK(dem.strain()[0] == 0.0);
        const auto& p = dem.particles();
        const double length = p.back().y_um + p.back().r_um - (p.front().y_um - p.front().r_um);
        CHECK(length == doctest::Approx(5 * myocyte_pitch_um(spec, 0.9)).epsilon(1e-5));
      }
    }

  // Fibroblasts in series do not shorten: M F M F M with free fibroblasts
  // gives the length-weighted strain; fixed fibroblasts hold the fibre.
  Tissue mixed;
  double y = 0;
  int prev_top = -1;
  for (int k = 0; k < 5; ++k) {
    const int first = static_cast<int>(mixed.particles.size());
    if (k % 2 == 0) {
      add_vertical_myocyte(mixed, 0, y);
      y += kMyocyteLength_um;
    } else {
      add_round_fibroblast(mixed, 0, y + kParticleRadius_um);
      y += 2 * kParticleRadius_um;
    }
    if (prev_top >= 0) mixed.add_bond(prev_top, first);
    prev_top = static_cast<int>(mixed.particles.size()) - 1;
  }
  mixed.finalise();
  {
    DemSpec spec;
    spec.strain_bodies = StrainBodies::bodies;
    DemSolver dem(mixed, spec);
    contract(dem, mixed, 0.9, 100, 600);
    const double length = 3 * myocyte_pitch_um(spec, 0.9) + 50;
    const auto& p = dem.particles();
    CHECK(p.back().y_um + p.back().r_um - (p.front().y_um - p.front().r_um) ==
          doctest::Approx(length).epsilon(1e-5));
    // The fit over 5 bodies of unequal spacing is not exactly the length ratio.
    const double expected = std::log(length / (3 * 125 + 50.0));
    CHECK(dem.strain()[1] == doctest::Approx(expected).epsilon(0.05));
    spec.fibroblasts_fixed = true;
    DemSolver fixed(mixed, spec);
    contract(fixed, mixed, 0.9, 100, 600);
    for (std::size_t i = 0; i < mixed.particles.size(); ++i)
      if (mixed.type[mixed.particles[i].cell] == CellType::fibroblast)
        CHECK(fixed.particles()[i].y_um == mixed.particles[i].y_um);
    CHECK(std::abs(fixed.strain()[1]) < std::abs(dem.strain()[1]));
  }

  // A small in-series tissue of myocytes only (fibres side by side, cells
  // aligned): along the fibre as the strand; across, the columns' lateral bonds
  // (pitch p = 23.57 um) return to their reference gaps, so the pitch grows by
  // twice the radius change.
  {
    const Tissue t = small_in_series(0.0);
    DemSpec spec;
    DemSolver dem(t, spec);
    contract(dem, t, 0.9, 200, 1000);
    const ClumpShape c = contracted_shape(spec.area_rule, spec.length_mode, kMyocyteParticles,
                                          kParticleRadius_um, kParticleSpacing_um, 0.9);
    const double p = kColumnPitch_um;
    CHECK(dem.strain()[1] == doctest::Approx(std::log(myocyte_pitch_um(spec, 0.9) / 125)).epsilon(5e-3));
    CHECK(dem.strain()[0] == doctest::Approx(std::log((p + 2 * (c.r - kParticleRadius_um)) / p)).epsilon(5e-3));
    CHECK(std::abs(dem.strain()[2]) < 1e-4);
  }
}

TEST_CASE("dem: a body gone non-finite stops the step with an error, never a silent NaN") {
  for (bool detect : {true, false}) {
    CAPTURE(detect);
    DemSpec spec;
    spec.contact_detection = detect;
    DemSolver dem(bonded_pair(), spec);
    dem.set_body_velocity(0, std::numeric_limits<double>::quiet_NaN(), 0, 0);
    CHECK_THROWS_WITH_AS(dem.step(dem.step_ms()), doctest::Contains("went unstable"), std::runtime_error);
  }
}

TEST_CASE("dem: contacts that form lower the stable step, a fixed step above it stops with both numbers") {
  // Two free disks 5 um apart, no bond: no stiffness limit at first (the step
  // is capped at 1 ms); once they are listed as a contact the stable step is
  // that of one contact, 0.8 sqrt(m / k') ~ 0.10 ms, so a fixed 0.2 ms is
  // refused then, while the automatic step follows.
  Tissue t;
  add_round_fibroblast(t, 0, 0);
  add_round_fibroblast(t, 2 * kParticleRadius_um + 5, 0);
  t.finalise();
  DemSpec spec;
  DemSolver automatic(t, spec);
  CHECK(automatic.stable_step_ms() == 1.0);
  spec.dt_ms = 0.2;
  DemSolver fixed(t, spec);
  for (DemSolver* dem : {&automatic, &fixed}) {
    dem->set_body_velocity(0, 1e-3, 0, 0);
    dem->set_body_velocity(1, -1e-3, 0, 0);
  }
  bool refused = false;
  for (int k = 0; k < 100 && !refused; ++k) {
    try {
      fixed.step(fixed.step_ms());
    } catch (const std::invalid_argument& e) {
      refused = true;
      CHECK(std::string(e.what()).find("new contacts lower the stable DEM step") != std::string::npos);
      CHECK(std::string(e.what()).find("mechanics.dt_ms 0.2") != std::string::npos);
    }
  }
  CHECK(refused);
  for (int k = 0; k < 100 && automatic.contacts().size() == 0; ++k) automatic.step(automatic.step_ms());
  REQUIRE(automatic.contacts().size() == 1);
  CHECK(automatic.stable_step_ms() < 0.2);
  CHECK(automatic.stable_step_ms() > 0.05);
}

TEST_CASE("dem: a step above the stable one is refused") {
  const Tissue t = small_in_series(0.4);
  DemSpec spec;
  DemSolver dem(t, spec);
  const double stable = dem.stable_step_ms();
  // Table 1 in-series: a fibroblast disk between clumps sets it, ~0.04 ms;
  // the seed's 0.004 ms is well inside.
  CHECK(stable > 0.004);
  CHECK(stable < 0.1);
  CHECK_NOTHROW(dem.step(stable));
  CHECK_THROWS_WITH_AS(dem.step(1.01 * stable), doctest::Contains("stable DEM step"), std::invalid_argument);
  spec.dt_ms = 2 * stable;
  CHECK_THROWS_WITH_AS(DemSolver(t, spec), doctest::Contains("exceeds the stable DEM step"), std::invalid_argument);
  // Stiffer contacts, smaller step: x 1.5 on fibroblast contacts, x 4 everywhere.
  spec.dt_ms = 0;
  spec.kn_N_per_m *= 4;
  spec.ks_N_per_m *= 4;
  CHECK(DemSolver(t, spec).stable_step_ms() == doctest::Approx(stable / 2).epsilon(1e-9));
  // Series inheritance halves the contacts' stiffness.
  DemSpec series;
  series.stiffness_inheritance = StiffnessInheritance::series;
  series.fibroblast_stiffness_factor = 1.5;
  DemSolver s(t, series);
  for (std::size_t k = 0; k < s.bonds().size(); ++k) {
    const bool fib = t.type[t.particles[s.bonds().p[k]].cell] == CellType::fibroblast ||
                     t.type[t.particles[s.bonds().q[k]].cell] == CellType::fibroblast;
    CHECK(s.bonds().kn[k] == doctest::Approx(13.0 * (fib ? 1.5 : 1.0)));
  }
}

TEST_CASE("dem: a contraction cycle with Table 1 parameters stays bounded and deterministic") {
  const Tissue t = testing::build_tissue(
      {{"builder", "in_series"}, {"width_mm", 0.3}, {"height_mm", 0.8}, {"fm_ratio", 0.41}}, 5);
  auto run = [&t] {
    DemSolver dem(t, DemSpec{});
    const int steps = 2000;
    double peak = 0;
    for (int k = 1; k <= steps; ++k) {
      const double lambda = 1 - 0.05 * (1 - std::cos(2 * M_PI * k / steps));  // 1 -> 0.9 -> 1
      dem.set_cell_length_ratios(ratios(t, lambda));
      dem.step(0.004);  // the seed's in-series step
      peak = std::max(peak, std::abs(dem.strain()[1]));
    }
    for (const auto& p : dem.particles()) REQUIRE(std::isfinite(p.x_um + p.y_um + p.r_um));
    CHECK(max_displacement_um(dem, t) < 60);
    CHECK(peak > 0.02);
    CHECK(peak < 0.2);
    CHECK(dem.broken_bonds() == 0);
    return dem.particles();
  };
  const auto a = run(), b = run();
  for (std::size_t i = 0; i < a.size(); ++i) REQUIRE((a[i].x_um == b[i].x_um && a[i].y_um == b[i].y_um));
}

TEST_CASE("dem: a bond breaks at its tensile strength and then holds no tension") {
  const Tissue t = bonded_pair();
  DemSpec spec;
  spec.tensile_strength_N = 1e-5;  // kn x 0.38 um of opening; the pair would reach ~5e-5 N
  DemSolver dem(t, spec);
  dem.set_body_velocity(0, -1e-2, 0, 0);
  dem.set_body_velocity(1, 1e-2, 0, 0);
  double max_tension = 0;
  for (int k = 0; k < 2000; ++k) {
    dem.step(1e-4);
    max_tension = std::max(max_tension, -dem.bonds().fn[0]);
  }
  CHECK(dem.broken_bonds() == 1);
  CHECK(max_tension < 1e-5);
  CHECK(max_tension > 0.9e-5);
  // Free flight after the break, the momentum kept.
  CHECK(dem.body(1).vx_m_per_s > 0);
  CHECK(dem.body(0).vx_m_per_s == doctest::Approx(-dem.body(1).vx_m_per_s));
  CHECK(dem.bonds().fn[0] == 0.0);
}

// Unbonded particles of different bodies that overlap, by brute force over all
// pairs (independent of the solver's grid): the deepest overlap [um], and
// whether every overlapping pair is on the solver's contact list.
struct OverlapCheck {
  double deepest_um = 0;
  bool all_listed = true;
};
OverlapCheck unbonded_overlaps(const DemSolver& dem, const Tissue& t) {
  std::vector<std::pair<int, int>> bonded, listed;
  for (const auto& b : t.bonds) bonded.emplace_back(std::min(b.p, b.q), std::max(b.p, b.q));
  for (std::size_t k = 0; k < dem.contacts().size(); ++k) listed.emplace_back(dem.contacts().p[k], dem.contacts().q[k]);
  std::sort(bonded.begin(), bonded.end());
  OverlapCheck out;
  const auto& p = dem.particles();
  for (int i = 0; i < static_cast<int>(p.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(p.size()); ++j) {
      if (dem.body_of_particle(i) == dem.body_of_particle(j)) continue;
      const double overlap = p[i].r_um + p[j].r_um - std::hypot(p[i].x_um - p[j].x_um, p[i].y_um - p[j].y_um);
      if (overlap <= 0 || std::binary_search(bonded.begin(), bonded.end(), std::make_pair(i, j))) continue;
      out.deepest_um = std::max(out.deepest_um, overlap);
      if (!std::binary_search(listed.begin(), listed.end(), std::make_pair(i, j))) out.all_listed = false;
    }
  return out;
}

TEST_CASE("dem: loose interstitial tissue contracts without bodies passing through one another") {
  // The interstitial layout is loose: chains of rotated clumps held sideways
  // by small fibroblast particles. Through a contraction cycle (every myocyte
  // 1 -> 0.9 -> 1 in 100 ms), particles that were not bonded meet; with
  // detection they push apart (overlaps stay those of a loaded linear contact,
  // F/kn < 2 um, and every overlapping pair is on the contact list) and the
  // tissue returns to its shape (residual strain < 0.01); without detection
  // (this solver before contact detection) bodies pass through one another by
  // more than half a myocyte's radius.
  const Tissue t = testing::build_tissue({{"builder", "interstitial"}, {"width_mm", 0.3}, {"height_mm", 1.2}}, 2);
  for (bool detect : {true, false}) {
    CAPTURE(detect);
    DemSpec spec;
    spec.contact_detection = detect;
    DemSolver dem(t, spec);
    const double period_ms = 100;
    double deepest = 0, peak_yy = 0;
    bool all_listed = true;
    for (int check = 1; check <= 4; ++check) {
      while (dem.time_ms() < check * period_ms / 4) {
        const double lambda = 1 - 0.05 * (1 - std::cos(2 * M_PI * dem.time_ms() / period_ms));
        dem.set_cell_length_ratios(ratios(t, lambda));
        dem.step(dem.step_ms());
        peak_yy = std::min(peak_yy, dem.strain()[1]);
      }
      const OverlapCheck o = unbonded_overlaps(dem, t);
      deepest = std::max(deepest, o.deepest_um);
      all_listed = all_listed && o.all_listed;
    }
    MESSAGE("detection ", detect, ": deepest unbonded overlap ", deepest, " um, peak eps_yy ", peak_yy,
            ", end strain ", dem.strain()[0], " ", dem.strain()[1], "; ", dem.report());
    CHECK(peak_yy < -0.05);  // it did contract
    if (detect) {
      CHECK(deepest < 2.0);
      CHECK(all_listed);
      CHECK(std::abs(dem.strain()[0]) < 0.01);
      CHECK(std::abs(dem.strain()[1]) < 0.01);
    } else {
      CHECK(deepest > 0.5 * kParticleRadius_um);
    }
  }
}

TEST_CASE("dem: a run gives the same bits on one thread and on two" * doctest::test_suite("threads")) {
  // Loose interstitial tissue through part of a twitch: bonds and detected
  // contacts (several blocks of each, so both threads have contacts to do),
  // list rebuilds, the automatic step. Forces are summed per particle in a
  // fixed order, never in the order the threads finish.
  const Tissue t = testing::build_tissue({{"builder", "interstitial"}, {"width_mm", 0.6}, {"height_mm", 1.6}}, 2);
  const int threads_before = omp_get_max_threads();
  auto run = [&t](int threads) {
    omp_set_num_threads(threads);
    DemSolver dem(t, DemSpec{});
    while (dem.time_ms() < 10) {
      const double lambda = 1 - 0.05 * (1 - std::cos(2 * M_PI * dem.time_ms() / 100));
      dem.set_cell_length_ratios(ratios(t, lambda));
      dem.step(dem.step_ms());
    }
    MESSAGE(threads, " threads: ", dem.report());
    CHECK(dem.bonds().size() > 512);  // blocks of 512
    CHECK(dem.contacts().size() > 512);
    CHECK(dem.contact_list_builds() > 1);
    return std::make_pair(dem.particles(), dem.strain());
  };
  const auto one = run(1), two = run(2);
  omp_set_num_threads(threads_before);
  for (std::size_t i = 0; i < one.first.size(); ++i)
    REQUIRE((one.first[i].x_um == two.first[i].x_um && one.first[i].y_um == two.first[i].y_um &&
             one.first[i].r_um == two.first[i].r_um));
  CHECK(one.second == two.second);
}
