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
  // Unit inconsistencies inside equations refused (else imported with the
  // numbers as written, and a warning each); see docs/topics/cellml_units.md.
  bool strict_units = false;
};

struct ImportResult {
  std::filesystem::path folder;
  std::vector<std::string> notes;
  // One per unit inconsistency inside an equation (UnitIssue::text()); also
  // listed in the generated source's header.
  std::vector<std::string> unit_warnings;
};

// Reads, translates and writes; ImportError (with the element's path) on
// anything it cannot translate, before anything is written. Structural faults
// (a connection between different dimensions, no time or membrane potential)
// are refused always; unit inconsistencies inside equations only with
// options.strict_units (all of them listed).
ImportResult import_cellml(const ImportOptions& options);

}  // namespace fibrodem::cellml
