// The .pvd collection (io/pvd_collection.hpp), read and written with pugixml.
#include "io/pvd_collection.hpp"
#include "util/number_text.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace fibrodem {
namespace {

// The collection's entries, file name -> time (ms), from the file if it exists.
std::map<std::string, double> read_entries(const std::filesystem::path& pvd) {
  std::map<std::string, double> entries;
  if (!std::filesystem::exists(pvd)) return entries;
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_file(pvd.c_str());
  if (!parsed)
    throw std::runtime_error("time collection " + pvd.string() + " cannot be read: " + parsed.description());
  const pugi::xml_node collection = doc.child("VTKFile").child("Collection");
  if (!collection)
    throw std::runtime_error("time collection " + pvd.string() + ": expected <VTKFile><Collection>");
  for (const pugi::xml_node d : collection.children("DataSet"))
    entries[d.attribute("file").value()] = d.attribute("timestep").as_double();
  return entries;
}
}  // namespace

void add_to_pvd(const std::filesystem::path& pvd, double t_ms, const std::string& dataset) {
  auto entries = read_entries(pvd);
  entries[dataset] = t_ms;
  std::vector<std::pair<double, std::string>> by_time;
  for (const auto& [file, t] : entries) by_time.emplace_back(t, file);
  std::sort(by_time.begin(), by_time.end());

  pugi::xml_document doc;
  pugi::xml_node root = doc.append_child("VTKFile");
  root.append_attribute("type") = "Collection";
  root.append_attribute("version") = "0.1";
  root.append_attribute("byte_order") = "LittleEndian";
  pugi::xml_node collection = root.append_child("Collection");
  for (const auto& [t, file] : by_time) {
    pugi::xml_node d = collection.append_child("DataSet");
    d.append_attribute("timestep") = format_number(t).c_str();  // ms
    d.append_attribute("group") = "";
    d.append_attribute("part") = "0";
    d.append_attribute("file") = file.c_str();
  }
  const std::filesystem::path temporary = pvd.string() + ".tmp";
  if (!doc.save_file(temporary.c_str(), "  "))
    throw std::runtime_error("time collection: cannot write " + temporary.string());
  std::error_code error;
  std::filesystem::rename(temporary, pvd, error);
  if (error) throw std::runtime_error("time collection: cannot replace " + pvd.string() + ": " + error.message());
}

}  // namespace fibrodem
