// The ranks of an MPI launch (`mpirun -n N fibrodem sweep ...`), or one rank
// when fibrodem was not launched by mpirun or was built without MPI (OpenMPI
// from Debian, found at configure time). A sweep spreads its runs over the
// ranks; rank 0 gathers their results and writes the tables.
#pragma once

#include <string>
#include <vector>

namespace fibrodem::cli {

class MpiRanks {
 public:
  MpiRanks();  // MPI_Init when launched by mpirun (its environment says so)
  ~MpiRanks();
  MpiRanks(const MpiRanks&) = delete;
  MpiRanks& operator=(const MpiRanks&) = delete;

  bool launched() const { return launched_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int on_this_host() const { return local_size_; }  // ranks sharing this machine's cores
  // Rank 0 receives every rank's text, in rank order; the others an empty list.
  std::vector<std::string> gather(const std::string& mine) const;

 private:
  bool launched_ = false;
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace fibrodem::cli
