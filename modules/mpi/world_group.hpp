// MPI_COMM_WORLD as a Simulation's RankGroup (run/rank_group.hpp).
#pragma once

#include <mpi.h>

#include <vector>

#include "apps/mpi_world.hpp"

namespace fibrodem::mpi {

// Collectives and point-to-point messages in the order the ranks call them
// (each call is made by every rank at the same point of the run).
class WorldGroup final : public RankGroup {
 public:
  explicit WorldGroup(const cli::MpiWorld& world) : world_(world) {}
  int rank() const override { return world_.rank(); }
  int size() const override { return world_.size(); }
  void exchange(const std::vector<HaloMessage>& messages) override;
  std::vector<std::vector<double>> gather(const std::vector<double>& mine) override;
  std::vector<std::string> gather_text(const std::string& mine) override { return world_.gather(mine); }
  void gather_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                   const int* offsets) override;
  void gather_all(const double* mine, std::size_t count, double* every_rank) override;
  void gather_all_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                       const int* offsets) override;

 private:
  static constexpr int kHaloTag = 17;
  const cli::MpiWorld& world_;
  std::vector<MPI_Request> requests_;
};

}  // namespace fibrodem::mpi
