#include "io/pvd_collection.hpp"

#include "util/runtime_module.hpp"

namespace fibrodem {

void add_to_pvd(const std::filesystem::path& pvd, double t_ms, const std::string& dataset) {
  static const PvdWriter* const writer = [] {
    using Entry = const PvdWriter* (*)();
    return reinterpret_cast<Entry>(module_entry("xml", kPvdWriterEntry, "needed to write a ParaView time collection"))();
  }();
  writer->add(pvd, t_ms, dataset);
}

}  // namespace fibrodem
