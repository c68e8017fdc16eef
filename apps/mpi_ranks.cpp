#include "apps/mpi_ranks.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#ifdef FIBRODEM_WITH_MPI
#include <mpi.h>
#endif

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

MpiRanks::MpiRanks() {
  if (!launched_by_mpi()) return;
  setenv(kRankPidVariable, std::to_string(getpid()).c_str(), 1);  // its children are not ranks
#ifdef FIBRODEM_WITH_MPI
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

namespace {

// MPI_COMM_WORLD as a RankGroup. Collectives and point-to-point messages in
// the order the ranks call them (each call is made by every rank at the
// same point of the run).
class WorldGroup final : public RankGroup {
 public:
  explicit WorldGroup(const MpiRanks& ranks) : ranks_(ranks) {}
  int rank() const override { return ranks_.rank(); }
  int size() const override { return ranks_.size(); }

  void exchange(const std::vector<HaloMessage>& messages) override {
#ifdef FIBRODEM_WITH_MPI
    requests_.resize(2 * messages.size());  // (the same size every step: allocated once)
    for (std::size_t k = 0; k < messages.size(); ++k)
      MPI_Irecv(messages[k].receive, static_cast<int>(messages[k].receive_count), MPI_DOUBLE, messages[k].rank,
                kHaloTag, MPI_COMM_WORLD, &requests_[2 * k]);
    for (std::size_t k = 0; k < messages.size(); ++k)
      MPI_Isend(messages[k].send, static_cast<int>(messages[k].send_count), MPI_DOUBLE, messages[k].rank, kHaloTag,
                MPI_COMM_WORLD, &requests_[2 * k + 1]);
    MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
#else
    (void)messages;
#endif
  }

  std::vector<std::vector<double>> gather(const std::vector<double>& mine) override {
    // Through the text gather, byte for byte: the values' bits arrive unchanged.
    std::string bytes(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(double));
    std::vector<std::vector<double>> all;
    for (const std::string& text : ranks_.gather(bytes)) {
      std::vector<double> values(text.size() / sizeof(double));
      std::copy(text.begin(), text.end(), reinterpret_cast<char*>(values.data()));
      all.push_back(std::move(values));
    }
    return all;
  }

  std::vector<std::string> gather_text(const std::string& mine) override { return ranks_.gather(mine); }

  void gather_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                   const int* offsets) override {
#ifdef FIBRODEM_WITH_MPI
    MPI_Gatherv(mine, static_cast<int>(count), MPI_DOUBLE, every_rank, counts, offsets, MPI_DOUBLE, 0,
                MPI_COMM_WORLD);
#else
    (void)counts;
    std::copy(mine, mine + count, every_rank + (offsets ? offsets[0] : 0));
#endif
  }

  void gather_all(const double* mine, std::size_t count, double* every_rank) override {
#ifdef FIBRODEM_WITH_MPI
    MPI_Allgather(mine, static_cast<int>(count), MPI_DOUBLE, every_rank, static_cast<int>(count), MPI_DOUBLE,
                  MPI_COMM_WORLD);
#else
    std::copy(mine, mine + count, every_rank);
#endif
  }

 private:
  static constexpr int kHaloTag = 17;
  const MpiRanks& ranks_;
#ifdef FIBRODEM_WITH_MPI
  std::vector<MPI_Request> requests_;
#endif
};

}  // namespace

std::shared_ptr<RankGroup> MpiRanks::group() const { return std::make_shared<WorldGroup>(*this); }

void MpiRanks::abort(int exit_code) const {
#ifdef FIBRODEM_WITH_MPI
  if (launched_) MPI_Abort(MPI_COMM_WORLD, exit_code);
#endif
  std::exit(exit_code);
}

}  // namespace fibrodem::cli
