// The partition module's interface (modules/partition): Scotch splits a graph
// given in compressed rows. Scotch is in a module opened on the first split
// into two parts or more (a run over MPI ranks), so that other processes do
// not load it and the libraries it needs (docs/topics/performance.md#start-up).
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

class GraphPartitioner {
 public:
  // Per vertex, its part in [0, parts), no part above (1 + imbalance) times
  // the mean vertex count; a function of the graph alone (fixed seed, one
  // thread). Throws std::runtime_error naming the failed step.
  virtual std::vector<int> split(const CompressedGraph& graph, int parts, double imbalance) const = 0;

 protected:
  ~GraphPartitioner() = default;
};

inline constexpr const char* kGraphPartitionerEntry = "fibrodem_graph_partitioner_v1";

// The module's partitioner, opened on first use.
const GraphPartitioner& graph_partitioner();

}  // namespace fibrodem
