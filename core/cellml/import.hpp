// `fibrodem import-cellml`: a CellML file in, a plugin folder out (NAME.cpp
// and CMakeLists.txt), written whole or not at all.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fibrodem::cellml {

struct ImportOptions {
  std::filesystem::path input;
  std::string name;
  std::filesystem::path out;  // empty: ./NAME
  std::string kind = "ionic";  // or "myofilament"
  std::vector<std::string> map;  // SIGNAL=component.variable
  std::string voltage;
  std::string stimulus;
  bool overwrite = false;
};

struct ImportResult {
  std::filesystem::path folder;
  std::vector<std::string> notes;
};

// Reads, translates and writes; ImportError (with the element's path) on
// anything it cannot translate, before anything is written.
ImportResult import_cellml(const ImportOptions& options);

}  // namespace fibrodem::cellml
