// The xml module's `fibrodem import-cellml` (apps/cellml_import_module.hpp):
// the CellML import, with pugixml and its own copy of the core layers the
// import uses, and what the command prints.
#include <iostream>

#include "apps/cellml_import_module.hpp"
#include "cellml/import.hpp"
#include "cellml/import_error.hpp"

namespace fibrodem::cli {
namespace {

int run_import(const cellml::ImportOptions& options) {
  try {
    const auto result = cellml::import_cellml(options);
    std::cout << "wrote " << (result.folder / (options.name + ".cpp")).string() << " and "
              << (result.folder / "CMakeLists.txt").string() << "\n";
    for (const auto& note : result.notes) std::cout << "  " << note << "\n";
    for (const auto& warning : result.unit_warnings) std::cerr << "warning: " << warning << "\n";
    if (!result.unit_warnings.empty())
      std::cerr << "warning: " << result.unit_warnings.size() << " unit inconsistenc"
                << (result.unit_warnings.size() == 1 ? "y" : "ies") << " imported with the numbers as written (listed in the plugin's header; "
                   "--strict-units refuses them)\n";
    const std::string build = (result.folder / "build").string();
    std::cout << "build it against an installed fibrodem:\n"
              << "  cmake -S " << result.folder.string() << " -B " << build
              << " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=<fibrodem's install prefix>\n"
              << "  cmake --build " << build << "\n";
    return 0;
  } catch (const cellml::ImportError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 5;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace
}  // namespace fibrodem::cli

extern "C" __attribute__((visibility("default"))) int fibrodem_cellml_import_v1(
    const fibrodem::cellml::ImportOptions* options) {
  return fibrodem::cli::run_import(*options);
}
