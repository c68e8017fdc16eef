// Every rank's beats (BeatBiomarkers) to rank 0 at the end of a split run,
// in rounds of a bounded number of beats a rank: rank 0 then holds every
// beat once and one round's numbers besides. (Gathered at once, every
// cell's beat would be held three times over on rank 0 at the end of an
// 846,279-cell run: 137 MB on top of the beats, its peak of memory.)
#pragma once

#include <cstddef>
#include <vector>

#include "measure/biomarkers.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

inline constexpr std::size_t kBeatsPerRound = 16384;

// Collective. On rank 0 `beats` becomes every rank's beats, rank 0's first
// within each round (in no further order: the caller sorts); on the other
// ranks it is left as it is.
void gather_beats_on_rank0(RankGroup& ranks, std::vector<BeatBiomarkers>& beats,
                           std::size_t beats_per_round = kBeatsPerRound);

}  // namespace fibrodem
