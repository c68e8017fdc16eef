// No DEM steps while the tissue is at rest (mechanics.skip_at_rest,
// core/run/mechanics_coupling.hpp, docs/topics/mechanics.md#rest). The coupling is
// driven as a run drives it, cell step by cell step: every myocyte's length
// ratio drifts by 1e-7 per ms (about a Rice myofilament's drift at rest under
// Rush-Larsen in the Fig. 3 scenes, whose strain reaches ~3e-6 by 30 ms)
// until a stimulus at kStimulus_ms, then follows a twitch. The reference is
// the same coupling with skip_at_rest off, so what is tested is what the
// skipping changes: the acceptance bounds (tests/support/dem_twitch.hpp:
// peaks within 1 %, course within 2 % RMS of the peak) on small tissues of
// both layouts; that most of the steps before the stimulus are skipped; that
// the stimulus wakes it at the first cell step whose lengths leave the
// tolerance; the same bits for any thread count; and a checkpoint taken
// asleep or awake resuming to the bits of the run never stopped.
#include <doctest/doctest.h>
#include <omp.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "run/mechanics_coupling.hpp"
#include "support/dem_twitch.hpp"

using namespace fibrodem;
using namespace fibrodem::test;

namespace {

constexpr double kStimulus_ms = 30;   // the twitch starts here
constexpr double kCellStep_ms = 0.1;  // an adaptive method's step at rest is longer; Rush-Larsen's 0.01
constexpr double kRestDrift_per_ms = 1e-7;

// As examples/fig3_interstitial_em.json.
DemSpec interstitial_spec() {
  DemSpec spec;
  spec.local_damping = 0.7;
  spec.multirate = true;
  spec.mass_scaling = 0.0025;
  return spec;
}

double length_ratio_at(double t_ms) {
  return t_ms <= kStimulus_ms ? 1 - kRestDrift_per_ms * t_ms
                              : (1 - kRestDrift_per_ms * kStimulus_ms) * twitch_lambda(t_ms - kStimulus_ms);
}

struct Driven {
  StrainCourse course;  // every 0.5 ms, at the cell steps' ends
  std::size_t skipped_before_stimulus = 0, skipped = 0;
  double first_awake_after_stimulus_ms = -1;
  bool asleep_at_stimulus = false;
};

// Cell steps of kCellStep_ms from `from_ms` to until_ms; t counted in steps
// (no accumulated rounding: the same times in every run).
void drive(const Tissue& t, MechanicsCoupling& m, long from_step, double until_ms, Driven& out) {
  std::vector<double> ratio(t.cell_count(), 1.0);
  for (long k = from_step + 1; k * kCellStep_ms <= until_ms + 1e-9; ++k) {
    const double t_ms = k * kCellStep_ms;
    for (std::size_t c = 0; c < t.cell_count(); ++c)
      if (t.type[c] == CellType::myocyte) ratio[c] = length_ratio_at(t_ms);
    m.advance(t_ms, ratio);
    if (k % 5 == 0) {
      out.course.xx.push_back(m.solver().strain()[0]);
      out.course.yy.push_back(m.solver().strain()[1]);
    }
    if (std::abs(t_ms - kStimulus_ms) < 1e-9) {
      out.skipped_before_stimulus = m.skipped_steps();
      out.asleep_at_stimulus = m.asleep();
    }
    if (t_ms > kStimulus_ms && !m.asleep() && out.first_awake_after_stimulus_ms < 0)
      out.first_awake_after_stimulus_ms = t_ms;
  }
  out.skipped = m.skipped_steps();
}

Driven run(const Tissue& t, DemSpec spec, bool skip, double until_ms) {
  spec.skip_at_rest = skip;
  MechanicsCoupling m(t, spec);
  Driven out;
  drive(t, m, 0, until_ms, out);
  MESSAGE(m.report());
  return out;
}

// The first cell step after the stimulus whose lengths leave the tolerance.
double first_change_ms() {
  for (long k = 1;; ++k)
    if (std::abs(length_ratio_at(k * kCellStep_ms) - 1) > MechanicsCoupling::kDriveTolerance) return k * kCellStep_ms;
}

void check_rest_against_every_step(const Tissue& t, const DemSpec& spec) {
  const double until_ms = kStimulus_ms + 150;
  const Driven every = run(t, spec, false, until_ms), skipping = run(t, spec, true, until_ms);
  CHECK(every.skipped == 0);
  // At rest from the start, asleep by the end of the first cell step. The
  // drift (3e-6 by the stimulus) stays inside the drive's tolerance, but
  // each cell step it stepped rings the tissue a little (the lengths it
  // missed asleep arrive over one cell step), so it wakes for a cell step
  // each time a body could have moved kRestDistance of a radius at that
  // ringing's speed and acceleration (a few ms): most steps are skipped.
  const double steps_before = kStimulus_ms / MechanicsCoupling(t, spec).solver().step_ms();
  MESSAGE(skipping.skipped_before_stimulus, " of ~", steps_before, " steps before the stimulus skipped, ",
          skipping.skipped, " in all");
  CHECK(static_cast<double>(skipping.skipped_before_stimulus) > 0.6 * steps_before);
  // Asleep when the stimulus comes, it wakes at the first cell step whose
  // lengths leave the tolerance.
  CHECK(skipping.asleep_at_stimulus);
  CHECK(skipping.first_awake_after_stimulus_ms == doctest::Approx(first_change_ms()));
  check_within_bounds(skipping.course, every.course);
}

}  // namespace

TEST_CASE("dem rest: in-series tissue skips its rest and keeps the twitch within the acceptance bounds") {
  check_rest_against_every_step(small_in_series_tissue(), DemSpec{});  // Table 1, as examples/fig3_in_series_em.json
}

TEST_CASE("dem rest: interstitial tissue skips its rest and keeps the twitch within the acceptance bounds") {
  check_rest_against_every_step(small_interstitial_tissue(), interstitial_spec());
}

TEST_CASE("dem rest: a moving body keeps it awake, a length change beyond the tolerance wakes it") {
  const Tissue t = small_interstitial_tissue();
  const DemSpec spec = interstitial_spec();
  MechanicsCoupling m(t, spec);
  const std::vector<double> rest(t.cell_count(), 1.0);
  m.advance(kCellStep_ms, rest);
  REQUIRE(m.asleep());  // built at rest: no velocity, no force
  // A body at 100 um/s: over a DEM step (0.037 ms) it moves ~4e-3 um, above
  // kRestDistance of the smallest radius (~1e-4 um: 1-4 um fibroblast disks).
  auto& dem = dynamic_cast<DemSolver&>(m.solver());
  MechanicsCoupling awake(t, spec);
  auto& moving = dynamic_cast<DemSolver&>(awake.solver());
  moving.set_body_velocity(0, 1e-4, 0, 0);
  awake.advance(kCellStep_ms, rest);
  CHECK_FALSE(awake.asleep());
  CHECK(awake.skipped_steps() == 0);
  CHECK(awake.solver().fastest_motion().speed_m_per_s > 0);
  // Round-off only: 1e-15 m/s would take 1e5 s to move 1e-10 m.
  CHECK(dem.fastest_motion().speed_m_per_s < 1e-14);
  // A length change beyond the tolerance wakes it at once, one within it does not.
  std::vector<double> ratio = rest;
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) ratio[c] = 1 - 0.5 * MechanicsCoupling::kDriveTolerance;
  m.advance(2 * kCellStep_ms, ratio);
  CHECK(m.asleep());
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) ratio[c] = 1 - 2 * MechanicsCoupling::kDriveTolerance;
  const std::size_t steps_before = dem.steps();
  m.advance(3 * kCellStep_ms, ratio);
  CHECK(dem.steps() > steps_before);
}

TEST_CASE("dem rest: the same bits for any thread count" * doctest::test_suite("threads")) {
  const Tissue t = small_interstitial_tissue();
  const DemSpec spec = interstitial_spec();
  const int threads_before = omp_get_max_threads();
  std::vector<Driven> runs;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    runs.push_back(run(t, spec, true, kStimulus_ms + 120));
  }
  omp_set_num_threads(threads_before);
  for (std::size_t k = 1; k < runs.size(); ++k) {
    CHECK(runs[k].skipped == runs[0].skipped);
    CHECK(runs[k].course.xx == runs[0].course.xx);
    CHECK(runs[k].course.yy == runs[0].course.yy);
  }
}

TEST_CASE("dem rest: a checkpoint asleep or awake resumes to the bits of the run never stopped") {
  const Tissue t = small_interstitial_tissue();
  const DemSpec spec = interstitial_spec();
  const double until_ms = kStimulus_ms + 60;
  MechanicsCoupling whole(t, spec);
  Driven whole_run;
  drive(t, whole, 0, until_ms, whole_run);
  // 20 ms: asleep; 40 ms: awake, in the twitch.
  for (const double stop_ms : {20.0, 40.0}) {
    const long stop_step = std::lround(stop_ms / kCellStep_ms);
    MechanicsCoupling first(t, spec);
    Driven before;
    drive(t, first, 0, stop_ms, before);
    CHECK(first.asleep() == (stop_ms < kStimulus_ms));
    CheckpointFields fields;
    first.save(fields);
    MechanicsCoupling resumed(t, spec);
    resumed.restore(fields, stop_step * kCellStep_ms);
    CHECK(resumed.asleep() == first.asleep());
    Driven after;
    drive(t, resumed, stop_step, until_ms, after);
    CHECK(resumed.skipped_steps() == whole.skipped_steps());
    CHECK(resumed.slept_ms() == whole.slept_ms());
    CHECK(resumed.solver().strain() == whole.solver().strain());
    const auto &a = whole.solver().particles(), &b = resumed.solver().particles();
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) REQUIRE((a[i].x_um == b[i].x_um && a[i].y_um == b[i].y_um));
  }
}

TEST_CASE("dem rest: the manifest key turns it off and names its path when not a boolean") {
  json defaults = json::object();
  JsonReader d(defaults, "mechanics");
  CHECK(read_dem_spec(d).skip_at_rest);
  json off = {{"skip_at_rest", false}};
  JsonReader o(off, "mechanics");
  CHECK_FALSE(read_dem_spec(o).skip_at_rest);
  json bad = {{"skip_at_rest", 1}};
  JsonReader b(bad, "mechanics");
  CHECK_THROWS_WITH(read_dem_spec(b), doctest::Contains("mechanics.skip_at_rest"));
}
