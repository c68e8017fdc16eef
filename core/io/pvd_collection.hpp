// A ParaView time collection (.pvd): VTK XML files, each with its time, that
// ParaView opens as one time series. It is rewritten whole (to a temporary
// file, then renamed) as each file is added, so that a run stopped at any
// point leaves a valid collection of the files it wrote (read and written
// with pugixml).
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

}  // namespace fibrodem
