// output.reentry's fibre-stretch frames with the DEM split over ranks
// (run/strain_fields.hpp): each rank takes its own cells' stretch at a
// sample, from its own and ghost bodies, and rank 0 gathers the frame. The
// reference is one process's frames of the same tissue through the same
// twitch; the split DEM agrees with it to rounding
// (tests/mechanics/test_dem_split.cpp: stretch within 1e-12), so the frames,
// which hold floats, must agree to one float's rounding (2^-23 near 1).
#include <doctest/doctest.h>

#include <cmath>

#include "run/strain_fields.hpp"
#include "support/dem_twitch.hpp"
#include "support/thread_ranks.hpp"
#include "tissue/cell_partition.hpp"

using namespace fibrodem;
using test::ThreadRanks;

namespace {

// Samples through the first 60 ms of the twitch: one on a step's end
// (sample_now) at 0, then every 5 ms a fraction into the step that holds it
// (due before the step, complete after), as the run takes them.
StretchFrames sampled(const Tissue& t, DemSolver& dem, StrainFields& fields) {
  std::vector<double> ratio(t.cell_count(), 1.0);
  fields.reserve_samples(13);
  fields.sample_now(0, dem);
  double next = 5;
  while (next <= 60) {
    const double t_old = dem.time_ms(), t_new = t_old + dem.step_ms();
    const bool due = next <= t_new;
    if (due) fields.due(next, (next - t_old) / (t_new - t_old), dem);
    test::twitch_step(t, dem, ratio);
    fields.complete(dem);
    if (due) next += 5;
  }
  return fields.stretch_frames();
}

}  // namespace

TEST_CASE("re-entry's fibre-stretch frames with the DEM split over ranks are one process's") {
  const Tissue t = test::small_in_series_tissue();
  const DemSpec spec;
  DemSolver one(t, spec);
  StrainFields one_fields(t);
  const StretchFrames reference = sampled(t, one, one_fields);
  REQUIRE(reference.count() == 13);

  const CellPartition partition = partition_cells(t, 3);
  const RankLayout layout = rank_layout(partition);
  std::vector<StretchFrames> frames(3, StretchFrames(t.cell_count()));
  ThreadRanks all(3, false);
  all.run([&](ThreadRanks::Group& group) {
    DemSolver dem(t, spec);
    dem.split_over_ranks(group, partition.part_of);
    StrainFields fields(t);
    fields.split_over(group, layout);
    frames[static_cast<std::size_t>(group.rank())] = sampled(t, dem, fields);
  });
  // Only rank 0 holds the frames.
  CHECK(frames[1].count() == 0);
  CHECK(frames[2].count() == 0);
  const StretchFrames& split = frames[0];
  REQUIRE(split.count() == reference.count());
  double largest = 0, moved = 0;
  for (std::size_t k = 0; k < split.count(); ++k) {
    CHECK(split.t_ms[k] == reference.t_ms[k]);
    const float *a = split.frame(k), *b = reference.frame(k);
    for (std::size_t c = 0; c < t.cell_count(); ++c) {
      if (std::isnan(b[c])) {
        CHECK(std::isnan(a[c]));
        continue;
      }
      largest = std::max(largest, static_cast<double>(std::abs(a[c] - b[c])));
      moved = std::max(moved, static_cast<double>(std::abs(b[c] - 1)));
    }
  }
  MESSAGE("stretch frames within ", largest, " of one process's (moved up to ", moved, ")");
  CHECK(moved > 0.01);  // the twitch stretched the cells: a frame of rest would prove nothing
  CHECK(largest <= 0x1p-23);
}
