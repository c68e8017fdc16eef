// The ranks of an MPI launch (`mpirun -n N fibrodem sweep ...`), or one rank
// when fibrodem was not launched by mpirun or was built without MPI (OpenMPI
// from Debian, found at configure time). A sweep spreads its runs over the
// ranks; rank 0 gathers their results and writes the tables. MPI itself is
// in the MPI module (apps/mpi_world.hpp), opened only under mpirun.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "apps/mpi_world.hpp"
#include "util/rank_group.hpp"

namespace fibrodem::cli {

class MpiRanks {
 public:
  // MPI_Init, through the MPI module, when launched by mpirun (its
  // environment says so). Throws std::runtime_error if the module is missing.
  MpiRanks();  ~MpiRanks();
  MpiRanks(const MpiRanks&) = delete;
  MpiRanks& operator=(const MpiRanks&) = delete;

  // The rank count the launcher gave this process's job, read from its
  // environment (OpenMPI's OMPI_COMM_WORLD_SIZE, MPICH's PMI_SIZE): 1 when
  // not launched by mpirun. Needs no MPI_Init, and holds in a build without
  // MPI too, whose N processes would otherwise each think they are alone.
  // 1 in a process a rank started (a sweep's child run inherits mpirun's
  // environment; MpiRanks marks it).
  static int launched_size();
  // This process's rank in that job, read from the same environment
  // (OMPI_COMM_WORLD_RANK, PMI_RANK, PMIX_RANK): 0 when not launched by mpirun.
  static int launched_rank();

  bool launched() const { return world_ != nullptr; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int on_this_host() const { return local_size_; }  // ranks sharing this machine's cores
  // Rank 0 receives every rank's text, in rank order; the others an empty list.
  std::vector<std::string> gather(const std::string& mine) const;
  // The ranks as a Simulation's RankGroup (one tissue split over them);
  // valid while this object lives.
  std::shared_ptr<RankGroup> group() const;
  // Ends every rank of the job (a rank whose part of a split run failed:
  // the others would wait for it at their next exchange).
  [[noreturn]] void abort(int exit_code) const;

 private:
  std::unique_ptr<MpiWorld> world_;  // null: not launched by mpirun, or a build without MPI
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace fibrodem::cli
