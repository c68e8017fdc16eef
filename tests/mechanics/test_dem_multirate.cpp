// Multirate DEM stepping (mechanics.multirate, core/mechanics/dem_multirate.cpp):
// the acceptance bounds (tests/support/dem_twitch.hpp), on a small
// in-series and a small interstitial tissue through a twitch: against the
// native solver (one step for every body, the native stable step, no mass
// scaling), the peak strains eps_xx and eps_yy within 1 % and the strain's
// time course within 2 % RMS of the peak; the same with mass scaling on the
// interstitial tissue (0.005, twice examples/fig3_interstitial_em.json's:
// the larger error of the two).
// Also: who takes substeps and how many, that the heavy bodies' step is
// longer than the native one, that internal forces leave the tissue's
// momentum near zero, the strain fitted to bodies, the same bits on one
// thread and two, and a checkpoint.
#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mechanics/dem_solver.hpp"
#include "support/dem_twitch.hpp"

using namespace fibrodem;
using namespace fibrodem::test;

namespace {

void advance(const Tissue& t, DemSolver& dem, double until_ms) {
  std::vector<double> ratio(t.cell_count(), 1.0);
  while (dem.time_ms() < until_ms) test::twitch_step(t, dem, ratio);
}

}  // namespace

TEST_CASE("dem multirate: interstitial tissue through a twitch keeps its strain within the acceptance bounds" * doctest::test_suite("slow")) {
  const Tissue t = small_interstitial_tissue();
  DemSpec native_spec;
  native_spec.local_damping = 0.7;  // as examples/fig3_interstitial_em.json
  DemSpec multirate_spec = native_spec;
  multirate_spec.multirate = true;
  const StrainCourse native = twitch(t, native_spec, 150), multirate = twitch(t, multirate_spec, 150);
  MESSAGE("step ", multirate.step_ms, " ms (", multirate.substeps, " substeps in ", multirate.steps,
          " steps) against ", native.step_ms, " ms native (", native.steps, " steps)");
  // Its 1-4 um fibroblast disks take substeps; the rest steps at the
  // clumps' pace, several times the native step.
  CHECK(multirate.light_bodies > 0);
  CHECK(multirate.step_ms > 2 * native.step_ms);
  CHECK(multirate.substeps > multirate.steps);
  check_within_bounds(multirate, native);
}

TEST_CASE("dem multirate: with mass scaling, interstitial tissue keeps its strain within the acceptance bounds" * doctest::test_suite("slow")) {
  const Tissue t = small_interstitial_tissue();
  DemSpec native_spec;
  native_spec.local_damping = 0.7;
  DemSpec spec = native_spec;
  spec.multirate = true;
  spec.mass_scaling = 0.005;  // the most docs/topics/mechanics.md allows alone
  const StrainCourse native = twitch(t, native_spec, 150), combined = twitch(t, spec, 150);
  MESSAGE("step ", combined.step_ms, " ms (", combined.substeps, " substeps in ", combined.steps, " steps)");
  // The scaled disks' step is longer: fewer substeps per step than without.
  DemSpec unscaled = spec;
  unscaled.mass_scaling = 0;
  const DemSolver a(t, spec), b(t, unscaled);
  CHECK(a.light_step_ms() > b.light_step_ms());
  check_within_bounds(combined, native);
}

TEST_CASE("dem multirate: in-series tissue through a twitch keeps its strain within the acceptance bounds" * doctest::test_suite("slow")) {
  const Tissue t = small_in_series_tissue();
  DemSpec native_spec;  // examples/fig3_in_series_em.json's mechanics: Table 1
  DemSpec multirate_spec = native_spec;
  multirate_spec.multirate = true;
  const StrainCourse native = twitch(t, native_spec, 150), multirate = twitch(t, multirate_spec, 150);
  MESSAGE("step ", multirate.step_ms, " ms (", multirate.substeps, " substeps in ", multirate.steps,
          " steps) against ", native.step_ms, " ms native");
  CHECK(multirate.step_ms >= native.step_ms);
  check_within_bounds(multirate, native);
}

TEST_CASE("dem multirate: the strain fitted to bodies holds the same bounds" * doctest::test_suite("slow")) {
  // (The body fit takes each body's displacement over the step: a light
  // body's last substep velocity is not its mean over the step.)
  const Tissue t = small_interstitial_tissue();
  DemSpec native_spec;
  native_spec.local_damping = 0.7;
  native_spec.strain_bodies = StrainBodies::bodies;
  DemSpec multirate_spec = native_spec;
  multirate_spec.multirate = true;
  check_within_bounds(twitch(t, multirate_spec, 150), twitch(t, native_spec, 150));
}

TEST_CASE("dem multirate: only disks lighter than the clumps take substeps, and the step is the heavy bodies'") {
  const Tissue t = small_interstitial_tissue();
  DemSpec spec;
  spec.multirate = true;
  const DemSolver dem(t, spec);
  REQUIRE(dem.light_bodies() > 0);
  std::size_t disks = 0;
  for (std::size_t b = 0; b < dem.body_count(); ++b) disks += !dem.body(b).clump;
  CHECK(dem.light_bodies() <= disks);
  // The light bodies' step is below the step of all, which is at least the
  // native one (the native step is the least critical step of every body).
  const DemSolver native(t, DemSpec{});
  CHECK(dem.light_step_ms() == doctest::Approx(native.stable_step_ms()).epsilon(1e-12));
  CHECK(dem.stable_step_ms() > dem.light_step_ms());
  // Two equal bonded disks and no clump: nothing to split, one rate.
  Tissue pair;
  add_round_fibroblast(pair, 0, 0);
  add_round_fibroblast(pair, 2 * kParticleRadius_um, 0);
  pair.add_bond(0, 1);
  pair.finalise();
  const DemSolver pair_multirate(pair, spec), pair_native(pair, DemSpec{});
  CHECK(pair_multirate.light_bodies() == 0);
  CHECK(pair_multirate.stable_step_ms() == pair_native.stable_step_ms());
}

TEST_CASE("dem multirate: internal forces leave the free tissue's momentum near zero") {
  // No fixed body and no local damping: the contacts are the only forces and
  // come in equal and opposite pairs. The native solver keeps sum m v at
  // zero to rounding; multirate gives the heavy end of a fast contact its
  // substeps' mean force half a step late, so sum m v is off by at most
  // ~h/2 times the fast contacts' force: far below the bodies' own momenta.
  const Tissue t = small_interstitial_tissue();
  DemSpec spec;
  spec.multirate = true;
  DemSolver dem(t, spec);
  advance(t, dem, 30);  // the cells shortening fastest
  double px = 0, py = 0, magnitude = 0;
  for (std::size_t b = 0; b < dem.body_count(); ++b) {
    const auto s = dem.body(b);
    px += s.mass_kg * s.vx_m_per_s;
    py += s.mass_kg * s.vy_m_per_s;
    magnitude += s.mass_kg * std::hypot(s.vx_m_per_s, s.vy_m_per_s);
  }
  MESSAGE("|sum m v| ", std::hypot(px, py), " kg m/s against sum m |v| ", magnitude);
  CHECK(magnitude > 0);
  CHECK(std::hypot(px, py) < 1e-3 * magnitude);
}

TEST_CASE("dem multirate: the same bits on one thread and on two" * doctest::test_suite("threads")) {
  const Tissue t = build_tissue({{"builder", "interstitial"}, {"width_mm", 0.6}, {"height_mm", 1.6}}, 2);
  const int threads_before = omp_get_max_threads();
  auto run = [&t](int threads) {
    omp_set_num_threads(threads);
    DemSpec spec;
    spec.multirate = true;
    DemSolver dem(t, spec);
    advance(t, dem, 10);
    CHECK(dem.light_bodies() > 0);
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

TEST_CASE("dem multirate: a checkpoint between steps resumes to the same bits") {
  const Tissue t = small_interstitial_tissue();
  DemSpec spec;
  spec.local_damping = 0.7;
  spec.multirate = true;
  spec.mass_scaling = 0.005;
  DemSolver first(t, spec);
  advance(t, first, 40);  // into the twitch: the contact list rebuilt
  REQUIRE(first.contact_list_builds() > 1);
  CheckpointFields fields;
  first.save(fields);
  DemSolver resumed(t, spec);
  resumed.load(fields);
  CHECK(resumed.substeps() == first.substeps());
  CHECK(resumed.light_step_ms() == first.light_step_ms());
  advance(t, first, 60);
  advance(t, resumed, 60);
  const auto &a = first.particles(), &b = resumed.particles();
  for (std::size_t i = 0; i < a.size(); ++i) REQUIRE((a[i].x_um == b[i].x_um && a[i].y_um == b[i].y_um));
  CHECK(first.strain() == resumed.strain());
  // A checkpoint of a run without multirate is refused by one with it.
  DemSpec native_spec = spec;
  native_spec.multirate = false;
  DemSolver native(t, native_spec);
  CheckpointFields native_fields;
  native.save(native_fields);
  DemSolver multirate(t, spec);
  CHECK_THROWS_WITH(multirate.load(native_fields), doctest::Contains("multirate"));
}

TEST_CASE("dem multirate: the manifest key reads a boolean and names its path otherwise") {
  json m = {{"multirate", true}};
  JsonReader r(m, "mechanics");
  CHECK(read_dem_spec(r).multirate);
  json defaults = json::object();
  JsonReader d(defaults, "mechanics");
  CHECK_FALSE(read_dem_spec(d).multirate);
  json bad = {{"multirate", 4}};
  JsonReader b(bad, "mechanics");
  CHECK_THROWS_WITH(read_dem_spec(b), doctest::Contains("mechanics.multirate"));
}
