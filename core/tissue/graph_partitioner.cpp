#include "tissue/graph_partitioner.hpp"

#include "util/runtime_module.hpp"

namespace fibrodem {

const GraphPartitioner& graph_partitioner() {
  static const GraphPartitioner& opened =
      module_object<GraphPartitioner>("partition", kGraphPartitionerEntry, "needed to split the cells over MPI ranks");
  return opened;
}

}  // namespace fibrodem
