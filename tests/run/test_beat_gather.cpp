// Every rank's beats to rank 0 in bounded rounds (run/beat_gather.hpp), on
// ranks that are threads: rank 0 must end with every beat of every rank,
// each once and unchanged, however the counts fall against the round.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "run/beat_gather.hpp"
#include "support/thread_ranks.hpp"

using namespace fibrodem;

namespace {

// Rank r's k-th beat: every field distinct from every other beat's.
BeatBiomarkers beat_of(int rank, int k) {
  BeatBiomarkers b;
  b.cell = 1000 * rank + k;
  b.type = k % 3 == 0 ? CellType::fibroblast : CellType::myocyte;
  b.beat = k % 4;
  b.activation_ms = 10.25 * rank + 0.5 * k;
  b.rmp_mV = -80 - 0.01 * k;
  b.apo_mV = 20 + 0.1 * rank;
  b.apd50_ms = k % 5 == 0 ? std::nan("") : 100 + k;
  b.apd90_ms = 250 + 0.001 * k;
  b.dvdt_max_mV_per_ms = 200 + rank;
  return b;
}

bool same(const BeatBiomarkers& a, const BeatBiomarkers& b) {
  const auto eq = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
  return a.cell == b.cell && a.type == b.type && a.beat == b.beat && eq(a.activation_ms, b.activation_ms) &&
         eq(a.rmp_mV, b.rmp_mV) && eq(a.apo_mV, b.apo_mV) && eq(a.apd50_ms, b.apd50_ms) && eq(a.apd90_ms, b.apd90_ms) &&
         eq(a.dvdt_max_mV_per_ms, b.dvdt_max_mV_per_ms);
}

}  // namespace

TEST_CASE("every rank's beats reach rank 0 once each, in rounds of a few") {
  // 4 ranks holding 7, 0, 3 and 12 beats, in rounds of 3: rank 1 sends in
  // no round, rank 2 in the first only, rank 3 in four; and in one round of 20.
  const std::vector<int> counts{7, 0, 3, 12};
  for (const std::size_t per_round : {std::size_t{3}, std::size_t{20}}) {
    CAPTURE(per_round);
    test::ThreadRanks ranks(4, false);
    std::vector<std::vector<BeatBiomarkers>> after(4);
    ranks.run([&](RankGroup& group) {
      const int r = group.rank();
      std::vector<BeatBiomarkers> beats;
      for (int k = 0; k < counts[static_cast<std::size_t>(r)]; ++k) beats.push_back(beat_of(r, k));
      gather_beats_on_rank0(group, beats, per_round);
      after[static_cast<std::size_t>(r)] = std::move(beats);
    });
    std::vector<BeatBiomarkers> all = after[0];
    REQUIRE(all.size() == 22);
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.cell < b.cell; });
    std::size_t i = 0;
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < counts[static_cast<std::size_t>(r)]; ++k, ++i) {
        CAPTURE(r);
        CAPTURE(k);
        CHECK(same(all[i], beat_of(r, k)));
      }
    // The other ranks keep their own.
    for (int r = 1; r < 4; ++r)
      CHECK(after[static_cast<std::size_t>(r)].size() == static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]));
  }
}
