#include <cstdio>
#include <string>

#include "apps/commands.hpp"
#include "apps/mpi_ranks.hpp"

namespace fibrodem::cli {

void print_failure(const std::string& kind, const std::string& what) {
  std::string line = kind + ": ";
  if (const int size = MpiRanks::launched_size(); size > 1)
    line += "rank " + std::to_string(MpiRanks::launched_rank()) + " of " + std::to_string(size) + ": ";
  line += what + "\n";
  std::fwrite(line.data(), 1, line.size(), stderr);  // unbuffered: one write
}

}  // namespace fibrodem::cli
