// The ranks of an MPI launch as the MPI module (libfibrodem-mpi.so,
// modules/mpi/, on Open MPI) gives them: the module is opened only under
// mpirun (apps/mpi_ranks.hpp), so that the command line does not load Open
// MPI and its libraries otherwise (docs/topics/performance.md#start-up).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "util/rank_group.hpp"

namespace fibrodem::cli {

class MpiWorld {
 public:
  virtual ~MpiWorld() = default;  // MPI_Finalize
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual int on_this_host() const = 0;  // ranks sharing this machine's cores
  // Rank 0 receives every rank's text, in rank order; the others an empty list.
  virtual std::vector<std::string> gather(const std::string& mine) const = 0;
  // MPI_COMM_WORLD as a RankGroup; valid while this object lives.
  virtual std::shared_ptr<RankGroup> group() const = 0;
  [[noreturn]] virtual void abort(int exit_code) const = 0;  // MPI_Abort
};

// The module's entry point, exported as C: MPI_Init, then the world (owned
// by the caller). Bump its version with any change to MpiWorld.
inline constexpr const char* kMpiWorldEntry = "fibrodem_mpi_world_v1";

}  // namespace fibrodem::cli
