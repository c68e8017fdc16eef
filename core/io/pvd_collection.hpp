// A ParaView time collection (.pvd): VTK XML files, each with its time, that
// ParaView opens as one time series. It is rewritten whole (to a temporary
// file, then renamed) as each file is added, so that a run stopped at any
// point leaves a valid collection of the files it wrote. The XML is read and
// written with pugixml in the xml module (modules/xml), opened on the first
// collection, so that a run without snapshots does not load pugixml
// (docs/topics/performance.md#start-up).
#pragma once

#include <filesystem>
#include <string>

namespace fibrodem {

// Adds `dataset` (a file name relative to the collection's folder) at time
// t_ms to the collection `pvd`, created if missing. An entry of the same
// file is replaced (a resumed run writing a snapshot again); entries are kept
// in time order. Throws std::runtime_error if the existing collection
// cannot be read or the new one cannot be written.
void add_to_pvd(const std::filesystem::path& pvd, double t_ms, const std::string& dataset);

// The xml module's side of add_to_pvd.
class PvdWriter {
 public:
  virtual void add(const std::filesystem::path& pvd, double t_ms, const std::string& dataset) const = 0;

 protected:
  ~PvdWriter() = default;
};

inline constexpr const char* kPvdWriterEntry = "fibrodem_pvd_writer_v1";

}  // namespace fibrodem
