// `fibrodem import-cellml MODEL.cellml --name NAME`: a plugin folder from a CellML model.
#include <CLI/CLI.hpp>
#include <iostream>

#include "apps/commands.hpp"
#include "cellml/import.hpp"
#include "cellml/import_error.hpp"
#include "util/plugin_name.hpp"

namespace fibrodem::cli {
namespace {

// What the import wrote, or its error; the exit status.
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


CLI::App* add_import_cellml_subcommand(CLI::App& app, cellml::ImportOptions& o) {
  auto* sub = app.add_subcommand("import-cellml", "Write a cell-model plugin (NAME.cpp, CMakeLists.txt) from a CellML 1.0, 1.1 or 2.0 model");
  sub->add_option("model", o.input, "the CellML file")->required();
  sub->add_option("--name", o.name, "the plugin's model name")->required();
  sub->add_option("--out", o.out, "the plugin folder to write (default ./NAME)");
  sub->add_option("--kind", o.kind, "ionic (default) or myofilament");
  sub->add_option("--map", o.map, "SIGNAL=component.variable: an output (Ca_i [mM], sarcomere_length [um], any name), or a myofilament model's input Ca_i (repeatable)");
  sub->add_option("--voltage", o.voltage, "component.variable of the membrane potential, when not evident");
  sub->add_option("--stimulus", o.stimulus, "component.variable of the CellML's stimulus current, when not evident");
  sub->add_flag("--overwrite", o.overwrite, "replace an existing plugin folder");
  sub->add_flag("--strict-units", o.strict_units,
                "refuse a model whose equations mix units (default: import with the numbers as written and warn)");
  return sub;
}

int import_cellml_command(const cellml::ImportOptions& options) {
  // The rule new-model and the SDK's CMake functions apply, checked before any work.
  if (!valid_plugin_name(options.name)) {
    std::cerr << "error: --name '" << options.name << "': expected " << kPluginNameRule << "\n";
    return 5;
  }
  return run_import(options);
}

}  // namespace fibrodem::cli
