#include "io/pvd_collection.hpp"

#include "util/runtime_module.hpp"

namespace fibrodem {

void add_to_pvd(const std::filesystem::path& pvd, double t_ms, const std::string& dataset) {
  static const PvdWriter& writer =
      module_object<PvdWriter>("xml", kPvdWriterEntry, "needed to write a ParaView time collection");
  writer.add(pvd, t_ms, dataset);
}

}  // namespace fibrodem
