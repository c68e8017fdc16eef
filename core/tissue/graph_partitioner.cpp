#include "tissue/graph_partitioner.hpp"

#include "util/runtime_module.hpp"

namespace fibrodem {

const GraphPartitioner& graph_partitioner() {
  static const GraphPartitioner* const opened = [] {
    using Entry = const GraphPartitioner* (*)();
    const auto entry = reinterpret_cast<Entry>(
        module_entry("partition", kGraphPartitionerEntry, "needed to split the cells over MPI ranks"));
    return entry();
  }();
  return *opened;
}

}  // namespace fibrodem
