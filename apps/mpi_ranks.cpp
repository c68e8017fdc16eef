#include "apps/mpi_ranks.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "util/runtime_module.hpp"

namespace fibrodem::cli {

namespace {

// Set by a rank for the processes it starts (a sweep's `fibrodem run`
// children inherit its environment, mpirun's variables included): its pid.
constexpr const char* kRankPidVariable = "FIBRODEM_MPI_RANK_PID";

// A launcher tells its processes through the environment: mpirun (OpenMPI:
// OMPI_COMM_WORLD_SIZE), MPICH's and Slurm's PMI (PMI_SIZE), PMIx (PMIX_RANK).
// A process that a rank started is not a rank itself.
bool launched_by_mpi() {
  if (const char* rank_pid = std::getenv(kRankPidVariable))
    if (std::atol(rank_pid) != static_cast<long>(getpid())) return false;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace

int MpiRanks::launched_size() {
  if (!launched_by_mpi()) return 1;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) {
      const int size = std::atoi(value);
      if (size > 0) return size;
    }
  return 1;
}

int MpiRanks::launched_rank() {
  if (!launched_by_mpi()) return 0;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* value = std::getenv(name)) return std::max(0, std::atoi(value));
  return 0;
}

MpiRanks::MpiRanks() {
  if (!launched_by_mpi()) return;
  setenv(kRankPidVariable, std::to_string(getpid()).c_str(), 1);  // its children are not ranks
#ifdef FIBRODEM_WITH_MPI
  // Global: Open MPI opens its own components against libmpi's symbols.
  using Entry = MpiWorld* (*)();
  const auto entry = reinterpret_cast<Entry>(
      module_entry("mpi", kMpiWorldEntry, "needed under mpirun, which launched this process", true));
  world_.reset(entry());
  rank_ = world_->rank();
  size_ = world_->size();
  local_size_ = world_->on_this_host();
#endif
}

MpiRanks::~MpiRanks() = default;

std::vector<std::string> MpiRanks::gather(const std::string& mine) const {
  if (!world_) return {mine};
  return world_->gather(mine);
}

namespace {

// One process as a RankGroup (a build without MPI): every collective is a copy.
class OneRank final : public RankGroup {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void exchange(const std::vector<HaloMessage>&) override {}
  std::vector<std::vector<double>> gather(const std::vector<double>& mine) override { return {mine}; }
  std::vector<std::string> gather_text(const std::string& mine) override { return {mine}; }
  void gather_into(const double* mine, std::size_t count, double* every_rank, const int*,
                   const int* offsets) override {
    std::copy(mine, mine + count, every_rank + (offsets ? offsets[0] : 0));
  }
  void gather_all(const double* mine, std::size_t count, double* every_rank) override {
    std::copy(mine, mine + count, every_rank);
  }
  void gather_all_into(const double* mine, std::size_t count, double* every_rank, const int*,
                       const int* offsets) override {
    std::copy(mine, mine + count, every_rank + (offsets ? offsets[0] : 0));
  }
};

}  // namespace

std::shared_ptr<RankGroup> MpiRanks::group() const {
  if (world_) return world_->group();
  return std::make_shared<OneRank>();
}

void MpiRanks::abort(int exit_code) const {
  if (world_) world_->abort(exit_code);
  std::exit(exit_code);
}

}  // namespace fibrodem::cli
