#include "apps/mpi_ranks.hpp"

#include <cstdlib>

#ifdef FIBRODEM_WITH_MPI
#include <mpi.h>
#endif

namespace fibrodem::cli {

#ifdef FIBRODEM_WITH_MPI
namespace {

// A launcher tells its processes through the environment: mpirun (OpenMPI:
// OMPI_COMM_WORLD_SIZE), MPICH's and Slurm's PMI (PMI_SIZE), PMIx (PMIX_RANK).
bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace
#endif

MpiRanks::MpiRanks() {
#ifdef FIBRODEM_WITH_MPI
  if (!launched_by_mpi()) return;
  MPI_Init(nullptr, nullptr);
  launched_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  // The ranks sharing this host (and its cores).
  MPI_Comm host;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &host);
  MPI_Comm_size(host, &local_size_);
  MPI_Comm_free(&host);
#endif
}

MpiRanks::~MpiRanks() {
#ifdef FIBRODEM_WITH_MPI
  if (launched_) MPI_Finalize();
#endif
}

std::vector<std::string> MpiRanks::gather(const std::string& mine) const {
  if (!launched_) return {mine};
#ifdef FIBRODEM_WITH_MPI
  int length = static_cast<int>(mine.size());
  std::vector<int> lengths(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (rank_ == 0) {
    int total = 0;
    for (int r = 0; r < size_; ++r) offsets[static_cast<std::size_t>(r)] = total, total += lengths[static_cast<std::size_t>(r)];
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  if (rank_ != 0) return {};
  std::vector<std::string> texts;
  for (int r = 0; r < size_; ++r)
    texts.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                               static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)])));
  return texts;
#else
  return {mine};
#endif
}

}  // namespace fibrodem::cli
