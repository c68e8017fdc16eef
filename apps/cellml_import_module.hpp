// `fibrodem import-cellml` reads CellML in the xml module (modules/xml), with
// pugixml, opened by that command alone so that no other command loads
// pugixml (docs/topics/performance.md#start-up).
#pragma once

#include "cellml/import.hpp"

namespace fibrodem::cli {

// The module's entry point: imports the model as `options` say and prints
// what it wrote (or the error); returns the command's exit status.
inline constexpr const char* kCellmlImportEntry = "fibrodem_cellml_import_v1";
using CellmlImportEntry = int (*)(const cellml::ImportOptions* options);

}  // namespace fibrodem::cli
