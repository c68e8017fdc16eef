// Biomarkers of a run split over MPI ranks (docs/guide/parallel.md): each rank's
// tracker measures its own cells only, numbered as in the tissue, and the
// gathered biomarkers.csv has the same bytes as one process's, whatever the
// ranks' threads and RMP method.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "measure/biomarkers.hpp"
#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");

namespace {

constexpr double kPi = 3.14159265358979323846;

// Cell c of a synthetic tissue: rest at -80 mV, a half-cosine upstroke to
// +20 mV over 1 ms from 10 + 3c ms, a linear repolarisation over 200 + 10c
// ms (each cell's beat differs, so a beat reported under the wrong number
// shows).
double synthetic_V(std::size_t c, double t) {
  const double up = 10.0 + 3.0 * static_cast<double>(c), fall = 200.0 + 10.0 * static_cast<double>(c);
  if (t <= up) return -80;
  if (t <= up + 1) return -80 + 50 * (1 - std::cos(kPi * (t - up)));
  if (t <= up + 1 + fall) return 20 - 100 * (t - up - 1) / fall;
  return -80;
}

// Steps a tracker over `cells` of the synthetic tissue (V given in the
// tracker's order) with beats from 5 ms; its beats.
std::vector<BeatBiomarkers> track(const std::vector<std::size_t>& cells, const std::vector<int>& numbers,
                                  bool pre_upstroke) {
  std::vector<BeatBiomarkers> beats;
  BiomarkerTracker tracker(std::vector<CellType>(cells.size(), CellType::myocyte), {5.0}, 0.0,
                           [&](const BeatBiomarkers& b) { beats.push_back(b); });
  if (!numbers.empty()) tracker.number_cells(numbers);
  if (pre_upstroke) tracker.use_pre_upstroke_rmp(2.0, 1.0);
  const double h = 0.01;
  std::vector<double> V(cells.size());
  const auto fill = [&](double t) {
    for (std::size_t i = 0; i < cells.size(); ++i) V[i] = synthetic_V(cells[i], t);
  };
  fill(0);
  tracker.start(0, V.data());
  for (long k = 0; k < 30000; ++k) {
    const double t_new = static_cast<double>(k + 1) * h;
    fill(t_new);
    tracker.step(static_cast<double>(k) * h, t_new, V.data(), nullptr);
  }
  tracker.finish();
  return beats;
}

// The split-run tests' sheet, 260 ms: through repolarisation.
json planar_wave() { return testing::split_sheet_planar_wave(260); }

}  // namespace

TEST_CASE("a rank's biomarker tracker measures its own cells as a tracker of every cell does") {
  const std::vector<std::size_t> every{0, 1, 2, 3, 4}, own{1, 3, 4};
  for (const bool pre_upstroke : {false, true}) {
    // The reference: one tracker over the whole synthetic tissue.
    const std::vector<BeatBiomarkers> whole = track(every, {}, pre_upstroke);
    REQUIRE(whole.size() == every.size());
    const std::vector<BeatBiomarkers> mine = track(own, {1, 3, 4}, pre_upstroke);
    REQUIRE(mine.size() == own.size());
    for (std::size_t i = 0; i < own.size(); ++i) {
      const BeatBiomarkers& a = whole[own[i]];
      const BeatBiomarkers& b = mine[i];
      CHECK(b.cell == static_cast<int>(own[i]));
      CHECK(b.beat == a.beat);
      // The same bits: each cell's measures read its own potentials only.
      CHECK(b.activation_ms == a.activation_ms);
      CHECK(b.rmp_mV == a.rmp_mV);
      CHECK(b.apo_mV == a.apo_mV);
      CHECK(b.apd50_ms == a.apd50_ms);
      CHECK(b.apd90_ms == a.apd90_ms);
      CHECK(b.dvdt_max_mV_per_ms == a.dvdt_max_mV_per_ms);
    }
    // The premise: the cells' beats differ (APD90 = fall 0.9 + 0.5 ms, cell by cell).
    CHECK(mine[0].apd90_ms != mine[1].apd90_ms);
  }
  BiomarkerTracker three(std::vector<CellType>(3, CellType::myocyte), {}, 0.0, [](const BeatBiomarkers&) {});
  CHECK_THROWS_AS(three.number_cells({1, 2}), std::invalid_argument);
}

TEST_CASE("mpirun -n 2 and 3: biomarkers.csv of a split run has one process's bytes") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_biomarkers");
  // Onset RMP measured on the step's threads (2 a rank: each thread's share
  // of the rank's cells), and pre-upstroke RMP measured whole.
  json threads = planar_wave();
  threads["solver"]["threads"] = 2;
  json pre_upstroke = planar_wave();
  pre_upstroke["output"]["biomarkers"] = {{"rmp", "pre_upstroke"}};
  std::ofstream(dir / "threads.json") << threads.dump();
  std::ofstream(dir / "pre_upstroke.json") << pre_upstroke.dump();

  REQUIRE(testing::run_scene("", dir / "threads.json", dir / "threads_one") == 0);
  const json one = json::parse(testing::read_file(dir / "threads_one" / "summary.json"));
  // The premise: the wave crossed the sheet and the cells repolarised.
  REQUIRE(one["cv_cm_per_s"].is_number());
  CHECK(one["mean_biomarkers"]["myocyte"]["apd90_ms"].get<double>() > 100);
  REQUIRE(testing::run_scene(testing::mpirun(3), dir / "threads.json", dir / "threads_three") == 0);
  for (const char* file : {"biomarkers.csv", "traces.csv"})
    CHECK(testing::read_file(dir / "threads_three" / file) == testing::read_file(dir / "threads_one" / file));

  REQUIRE(testing::run_scene("", dir / "pre_upstroke.json", dir / "pre_upstroke_one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "pre_upstroke.json", dir / "pre_upstroke_two") == 0);
  CHECK(testing::read_file(dir / "pre_upstroke_two" / "biomarkers.csv") ==
        testing::read_file(dir / "pre_upstroke_one" / "biomarkers.csv"));
}

TEST_SUITE_END();
