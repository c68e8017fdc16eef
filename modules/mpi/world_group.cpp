#include "world_group.hpp"

#include <algorithm>

namespace fibrodem::mpi {

void WorldGroup::exchange(const std::vector<HaloMessage>& messages) {
  requests_.resize(2 * messages.size());  // (the same size every step: allocated once)
  for (std::size_t k = 0; k < messages.size(); ++k)
    MPI_Irecv(messages[k].receive, static_cast<int>(messages[k].receive_count), MPI_DOUBLE, messages[k].rank,
              kHaloTag, MPI_COMM_WORLD, &requests_[2 * k]);
  for (std::size_t k = 0; k < messages.size(); ++k)
    MPI_Isend(messages[k].send, static_cast<int>(messages[k].send_count), MPI_DOUBLE, messages[k].rank, kHaloTag,
              MPI_COMM_WORLD, &requests_[2 * k + 1]);
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
}

std::vector<std::vector<double>> WorldGroup::gather(const std::vector<double>& mine) {
  // Through the text gather, byte for byte: the values' bits arrive unchanged.
  std::string bytes(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(double));
  std::vector<std::vector<double>> all;
  for (const std::string& text : world_.gather(bytes)) {
    std::vector<double> values(text.size() / sizeof(double));
    std::copy(text.begin(), text.end(), reinterpret_cast<char*>(values.data()));
    all.push_back(std::move(values));
  }
  return all;
}

void WorldGroup::gather_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                             const int* offsets) {
  MPI_Gatherv(mine, static_cast<int>(count), MPI_DOUBLE, every_rank, counts, offsets, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

void WorldGroup::gather_all(const double* mine, std::size_t count, double* every_rank) {
  MPI_Allgather(mine, static_cast<int>(count), MPI_DOUBLE, every_rank, static_cast<int>(count), MPI_DOUBLE,
                MPI_COMM_WORLD);
}

void WorldGroup::gather_all_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                                 const int* offsets) {
  MPI_Allgatherv(mine, static_cast<int>(count), MPI_DOUBLE, every_rank, counts, offsets, MPI_DOUBLE, MPI_COMM_WORLD);
}

}  // namespace fibrodem::mpi
