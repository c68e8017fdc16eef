// The MPI module's entry point: MPI_COMM_WORLD as an MpiWorld (apps/mpi_world.hpp).
#include <mpi.h>

#include <cstdlib>

#include "apps/mpi_world.hpp"
#include "world_group.hpp"

namespace fibrodem::mpi {
namespace {

class OpenMpiWorld final : public cli::MpiWorld {
 public:
  OpenMpiWorld() {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    // The ranks sharing this host (and its cores).
    MPI_Comm host;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &host);
    MPI_Comm_size(host, &local_size_);
    MPI_Comm_free(&host);
  }
  ~OpenMpiWorld() override { MPI_Finalize(); }
  OpenMpiWorld(const OpenMpiWorld&) = delete;
  OpenMpiWorld& operator=(const OpenMpiWorld&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int on_this_host() const override { return local_size_; }

  std::vector<std::string> gather(const std::string& mine) const override {
    int length = static_cast<int>(mine.size());
    std::vector<int> lengths(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (rank_ == 0) {
      int total = 0;
      for (int r = 0; r < size_; ++r) offsets[static_cast<std::size_t>(r)] = total, total += lengths[static_cast<std::size_t>(r)];
      all.resize(static_cast<std::size_t>(total));
    }
    MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
                MPI_COMM_WORLD);
    if (rank_ != 0) return {};
    std::vector<std::string> texts;
    for (int r = 0; r < size_; ++r)
      texts.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                                 static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)])));
    return texts;
  }

  std::shared_ptr<RankGroup> group() const override { return std::make_shared<WorldGroup>(*this); }

  [[noreturn]] void abort(int exit_code) const override {
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::exit(exit_code);
  }

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace
}  // namespace fibrodem::mpi

extern "C" __attribute__((visibility("default"))) fibrodem::cli::MpiWorld* fibrodem_mpi_world_v1() {
  return new fibrodem::mpi::OpenMpiWorld();
}
