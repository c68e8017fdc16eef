// How cells are shared between threads: every cell computed exactly once
// whatever the measured costs, and solver.threads "auto" falling back to one
// thread when two measure slower (a machine whose other core is taken).
#include <doctest/doctest.h>

#include <omp.h>

#include <atomic>
#include <vector>

#include "model/block_schedule.hpp"
#include "model/simd.hpp"
#include "model/work_split.hpp"

using namespace fibrodem;

namespace {

// Blocks of kCellsPerBlock cells over populations of the given sizes, and
// with tissue_index, the cells' places in a tissue (ascending per population).
std::vector<CellRange> blocks_of(const std::vector<std::size_t>& sizes,
                                 const std::vector<std::vector<int>>* tissue_index = nullptr) {
  std::vector<CellRange> blocks;
  for (std::size_t p = 0; p < sizes.size(); ++p)
    for (std::size_t begin = 0; begin < sizes[p]; begin += kCellsPerBlock)
      blocks.push_back({p, begin, std::min(sizes[p], begin + kCellsPerBlock),
                        tissue_index ? (*tissue_index)[p].data() : nullptr});
  return blocks;
}

// A tissue of `cells` cells whose every fourth cell is a fibroblast (population 1), the rest myocytes (0).
std::vector<std::vector<int>> mixed_tissue(int cells) {
  std::vector<std::vector<int>> index(2);
  for (int c = 0; c < cells; ++c) index[c % 4 == 3 ? 1 : 0].push_back(c);
  return index;
}

}  // namespace

TEST_CASE("the block schedule computes every cell once, in pieces within blocks, for any costs and thread count" * doctest::test_suite("threads")) {
  const std::vector<std::size_t> sizes{2900, 229, 1};  // the Fig. 3 in-series tissue's mix, and a lone cell
  // Cut in the blocks' order, or at places in a tissue where the populations interleave.
  std::vector<std::vector<int>> tissue(3);
  for (int c = 0; c < 3130; ++c) tissue[c == 1500 ? 2 : c % 13 == 0 && tissue[1].size() < 229 ? 1 : 0].push_back(c);
  REQUIRE(tissue[0].size() == sizes[0]);
  const int saved_threads = omp_get_max_threads();
  for (const bool by_tissue : {false, true})
  for (int threads : {1, 2, 3}) {
    CAPTURE(by_tissue);
    CAPTURE(threads);
    const auto blocks = blocks_of(sizes, by_tissue ? &tissue : nullptr);
    omp_set_num_threads(threads);
    BlockSchedule schedule;
    std::vector<std::vector<std::atomic<int>>> seen;
    for (std::size_t s : sizes) seen.emplace_back(s);
    std::atomic<int> after_all_calls{0};
    // Steps whose cost per cell differs between populations and from step to
    // step, so that the runs are re-cut inside blocks.
    for (int step = 0; step < 40; ++step) {
      for (auto& population : seen)
        for (auto& cell : population) cell.store(0);
      after_all_calls = 0;
      schedule.run(
          blocks,
          [&](const CellRange& piece) {
            // Within one block, at a whole SIMD width from the block's start unless at its end.
            REQUIRE(piece.begin < piece.end);
            REQUIRE(piece.begin / kCellsPerBlock == (piece.end - 1) / kCellsPerBlock);
            REQUIRE((piece.begin % kCellsPerBlock) % simd::kLanes == 0);
            volatile double work = 0;
            const int weight = piece.population == 0 ? 1 + step % 3 : 5;
            for (std::size_t c = piece.begin; c < piece.end; ++c) {
              for (int k = 0; k < 50 * weight; ++k) work = work + 1e-9;
              seen[piece.population][c].fetch_add(1);
            }
          },
          [&](int, int team) {
            CHECK(team >= 1);
            after_all_calls.fetch_add(1);
          });
      for (std::size_t p = 0; p < sizes.size(); ++p)
        for (std::size_t c = 0; c < sizes[p]; ++c)
          if (seen[p][c].load() != 1) FAIL("population ", p, " cell ", c, " computed ", seen[p][c].load(), " times");
      CHECK(after_all_calls.load() >= 1);
      CHECK(after_all_calls.load() <= threads);
    }
  }
  omp_set_num_threads(saved_threads);
}

TEST_CASE("runs cut at tissue indices: each thread's own cells are one stretch of the tissue, in every population" * doctest::test_suite("threads")) {
  // Thread t's run writes the new potentials of its own stretch of the
  // tissue only (the populations' cells are spread over all of it).
  const auto tissue = mixed_tissue(3129);
  const std::vector<std::size_t> sizes{tissue[0].size(), tissue[1].size()};
  const auto blocks = blocks_of(sizes, &tissue);
  const int saved_threads = omp_get_max_threads();
  for (int threads : {2, 3}) {
    CAPTURE(threads);
    omp_set_num_threads(threads);
    BlockSchedule schedule;
    for (int step = 0; step < 5; ++step)
      schedule.run(
          blocks,
          [](const CellRange& piece) {
            volatile double work = 0;  // (costs to measure: the runs are cut at equal shares of them)
            for (std::size_t k = 0; k < 50 * (piece.end - piece.begin); ++k) work = work + 1e-9;
          },
          nullptr);
    int last_end = -1;  // the tissue index after the previous thread's stretch
    for (int t = 0; t < threads; ++t) {
      int first = 1 << 30, last = -1;
      std::size_t cells = 0;
      for (const CellRange& piece : schedule.run_of(t)) {
        first = std::min(first, piece.tissue_index[piece.begin]);
        last = std::max(last, piece.tissue_index[piece.end - 1]);
        cells += piece.end - piece.begin;
      }
      CAPTURE(t);
      CHECK(cells > 0);
      // Stretches meet, overlapping by less than a SIMD width of each
      // population (each population's cut is rounded to a whole width; a
      // fibroblast every 4 cells: within 4 kLanes tissue cells).
      CHECK(first > last_end - 4 * static_cast<int>(simd::kLanes));
      CHECK(first < last_end + 4 * static_cast<int>(simd::kLanes) + 4);
      last_end = last + 1;
    }
    CHECK(last_end == 3129);
  }
  omp_set_num_threads(saved_threads);
}

TEST_CASE("solver.threads auto: the governor keeps the faster thread count and tries the other again later" * doctest::test_suite("threads")) {
  const int saved_threads = omp_get_max_threads();
  ThreadGovernor governor;
  CHECK_FALSE(governor.adapting());
  governor.adapt(2);
  REQUIRE(governor.adapting());
  // A machine whose other core is taken: two threads take 300 us a call, one 100 us.
  auto wall_s = [](int threads) { return threads > 1 ? 300e-6 : 100e-6; };
  long calls = 0;
  int first_switch_at = -1;
  for (; calls < 20000; ++calls) {
    const int threads = governor.threads();
    governor.record(threads, wall_s(threads));
    if (governor.switches() == 1 && first_switch_at < 0) first_switch_at = static_cast<int>(calls);
  }
  // It starts on two threads, tries one after its first stretch (512 calls)
  // for 64 calls, and switches then.
  CHECK(first_switch_at == 512 + 64 - 1);
  CHECK(governor.switches() == 1);  // two threads never win a trial again
  CHECK(omp_get_max_threads() == governor.threads());  // the run's other loops follow it
  // Trials of two threads grow rarer as they keep losing (stretches double up
  // to 16384 calls): after the switch, 19424 calls hold trials after 512, 1024,
  // 2048, 4096, 8192 calls: 5 x 64 calls on two threads.
  CHECK(governor.calls_on_more() == 512 + 5 * 64);
  CHECK(governor.calls_on_one() == 20000 - governor.calls_on_more());

  // The machine quietens: two threads now take 60 us, and the next trial wins.
  for (int k = 0; k < 20000; ++k) {
    const int threads = governor.threads();
    governor.record(threads, threads > 1 ? 60e-6 : 100e-6);
  }
  CHECK(governor.switches() == 2);
  CHECK(governor.threads() == 2);
  omp_set_num_threads(saved_threads);
}

TEST_CASE("a core lent to the writer: the cells step on one thread fewer, unmeasured, until it is given back" * doctest::test_suite("threads")) {
  const int saved_threads = omp_get_max_threads();
  ThreadGovernor fixed;
  fixed.use(2);
  CHECK(fixed.threads() == 2);
  fixed.lend(1);
  CHECK(fixed.threads() == 1);
  CHECK(fixed.chosen() == 2);  // what the run's notes report
  CHECK(omp_get_max_threads() == 1);  // the run's other loops (DEM) follow it
  fixed.lend(0);
  CHECK(fixed.threads() == 2);
  CHECK(omp_get_max_threads() == 2);
  ThreadGovernor single;
  single.use(1);
  single.lend(1);
  CHECK(single.threads() == 1);  // never below one thread

  // solver.threads auto: calls made while a core is lent do not count
  // towards its stretches and trials. Two threads take 300 us a call, one
  // 100 us (as in the governor's test above), but 1000 calls on a lent core
  // change nothing: the first switch still comes after 512 + 64 measured calls.
  ThreadGovernor governor;
  governor.adapt(2);
  governor.lend(1);
  for (int k = 0; k < 1000; ++k) governor.record(governor.threads(), 100e-6);
  CHECK(governor.switches() == 0);
  CHECK(governor.calls_on_one() == 1000);
  governor.lend(0);
  int first_switch_at = -1;
  for (int k = 0; k < 1000 && first_switch_at < 0; ++k) {
    const int threads = governor.threads();
    governor.record(threads, threads > 1 ? 300e-6 : 100e-6);
    if (governor.switches() == 1) first_switch_at = k;
  }
  CHECK(first_switch_at == 512 + 64 - 1);
  omp_set_num_threads(saved_threads);
}
