// Splitting a graph given in compressed rows, with Scotch (Debian
// libscotch-dev, 32-bit SCOTCH_Num): the cell graph over the ranks of a run
// over MPI (tissue/cell_partition.hpp).
#pragma once

#include <cstddef>
#include <vector>

namespace fibrodem {

// A symmetric graph without loops in compressed rows: the neighbours of
// vertex v are neighbours[row_start[v] .. row_start[v + 1]), each edge listed
// from both ends.
struct CompressedGraph {
  std::vector<int> row_start, neighbours;
};

// Per vertex, its part in [0, parts), no part above (1 + imbalance) times the
// mean vertex count; a function of the graph alone (fixed seed, one thread).
// Throws std::runtime_error naming the failed step.
std::vector<int> split_graph(const CompressedGraph& graph, int parts, double imbalance);

}  // namespace fibrodem
