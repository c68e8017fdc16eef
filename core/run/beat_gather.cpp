#include "run/beat_gather.hpp"

#include <algorithm>

namespace fibrodem {

namespace {

// A beat as numbers (its integers are exact in a double).
constexpr std::size_t kBeatFields = 9;

void pack(const BeatBiomarkers& b, std::vector<double>& into) {
  into.insert(into.end(),
              {static_cast<double>(b.cell), static_cast<double>(static_cast<int>(b.type)), static_cast<double>(b.beat),
               b.activation_ms, b.rmp_mV, b.apo_mV, b.apd50_ms, b.apd90_ms, b.dvdt_max_mV_per_ms});
}

BeatBiomarkers unpack(const double* v) {
  BeatBiomarkers b;
  b.cell = static_cast<int>(v[0]);
  b.type = static_cast<CellType>(static_cast<int>(v[1]));
  b.beat = static_cast<int>(v[2]);
  b.activation_ms = v[3];
  b.rmp_mV = v[4];
  b.apo_mV = v[5];
  b.apd50_ms = v[6];
  b.apd90_ms = v[7];
  b.dvdt_max_mV_per_ms = v[8];
  return b;
}

// Values rank r sends in the round starting at its beat `first`.
int round_values(double count, std::size_t first, std::size_t per_round) {
  const auto n = static_cast<std::size_t>(count);
  return static_cast<int>(kBeatFields * std::min(n - std::min(n, first), per_round));
}

}  // namespace

void gather_beats_on_rank0(RankGroup& ranks, std::vector<BeatBiomarkers>& beats, std::size_t per_round) {
  const auto size = static_cast<std::size_t>(ranks.size());
  const bool root = ranks.rank() == 0;
  const double own_count = static_cast<double>(beats.size());
  std::vector<double> counts(size);
  ranks.gather_all(&own_count, 1, counts.data());
  std::size_t total = 0, most = 0;
  for (const double c : counts)
    total += static_cast<std::size_t>(c), most = std::max(most, static_cast<std::size_t>(c));
  std::vector<BeatBiomarkers> own;
  if (root) {
    own.swap(beats);
    beats.reserve(total);
  }
  const std::vector<BeatBiomarkers>& sent = root ? own : beats;
  std::vector<double> packed, received;
  std::vector<int> values(size), offsets(size);
  for (std::size_t first = 0; first < most; first += per_round) {
    packed.clear();
    for (std::size_t k = first; k < std::min(sent.size(), first + per_round); ++k) pack(sent[k], packed);
    if (root) {
      int at = 0;
      for (std::size_t r = 0; r < size; ++r) {
        values[r] = round_values(counts[r], first, per_round);
        offsets[r] = at;
        at += values[r];
      }
      received.resize(static_cast<std::size_t>(at));
    }
    ranks.gather_into(packed.data(), packed.size(), received.data(), values.data(), offsets.data());
    if (root)
      for (std::size_t k = 0; k + kBeatFields <= received.size(); k += kBeatFields)
        beats.push_back(unpack(&received[k]));
  }
}

}  // namespace fibrodem
