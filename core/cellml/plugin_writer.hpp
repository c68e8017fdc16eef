// Writes a fibrodem cell-model plugin (one .cpp in the form of the
// hand-written ones, and a CMakeLists.txt for the SDK) from an analysed CellML
// model, converting to fibrodem's conventions at the boundary (ms, mV,
// whole-cell pA, pF, mM for Ca_i).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cellml/model_analysis.hpp"

namespace fibrodem::cellml {

struct WriterOptions {
  std::string name;                          // the plugin's model name
  bool myofilament = false;                  // --kind myofilament
  std::map<std::string, std::string> map;    // signal -> component.variable (--map)
  std::string voltage;                       // component.variable of V, when not evident
  std::string stimulus;                      // component.variable of the stimulus, when not evident
  std::string source_name;                   // the CellML file's name, for the header
};

struct GeneratedPlugin {
  std::string cpp;
  std::string cmake;
  std::vector<std::string> notes;  // what was converted, removed, recognised (also in the .cpp's header)
};

GeneratedPlugin write_plugin(const Model& model, const WriterOptions& options);

}  // namespace fibrodem::cellml
