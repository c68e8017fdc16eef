// The ranks one run is split over (docs/guide/parallel.md): what a Simulation
// needs of them. The command line implements it over MPI (apps/mpi_ranks.hpp);
// the core itself does not link MPI.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace fibrodem {

// One message of a halo exchange with one other rank: `send_count` values
// from `send` go to it while `receive_count` values from it land in
// `receive` (both sides agree on the counts: tissue/rank_cells.hpp).
struct HaloMessage {
  int rank = -1;
  const double* send = nullptr;
  std::size_t send_count = 0;
  double* receive = nullptr;
  std::size_t receive_count = 0;
};

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every message sent and received; returns when all have arrived. Called
  // by every rank at the same point (each with its own neighbours).
  virtual void exchange(const std::vector<HaloMessage>& messages) = 0;
  // Rank 0 receives every rank's values, in rank order; the others an empty
  // list. (Collective: every rank calls it.)
  virtual std::vector<std::vector<double>> gather(const std::vector<double>& mine) = 0;
  virtual std::vector<std::string> gather_text(const std::string& mine) = 0;
  // Rank 0 receives counts[r] values from each rank r into every_rank from
  // offsets[r] (the caller's buffer: nothing is allocated); each rank sends
  // its `count`. Only rank 0 reads counts and offsets and writes every_rank.
  // What a gather repeated during the run needs (output.reentry's samples).
  // (Collective: every rank calls it.)
  virtual void gather_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                           const int* offsets) = 0;
  // Every rank receives every rank's `count` values, in rank order, in
  // every_rank (count x size() values, the caller's: nothing is allocated).
  // What a reduction the same on every rank needs (run/rank_reductions.hpp):
  // each rank then adds or compares the same values in the same order.
  virtual void gather_all(const double* mine, std::size_t count, double* every_rank) = 0;
  // Every rank receives counts[r] values from each rank r into every_rank
  // from offsets[r] (the caller's buffer), each rank sending its `count`
  // (counts[rank()]): what the DEM over ranks needs to make every body's
  // state known to every rank (mechanics/dem_split.hpp). (Collective.)
  virtual void gather_all_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                               const int* offsets) = 0;
};

}  // namespace fibrodem
