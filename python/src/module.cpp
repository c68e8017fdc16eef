// fibrodem._core: the binding of the core library. Nothing here simulates:
// every call goes to the same core code as the command line.
#include <pybind11/pybind11.h>

#include "binding.hpp"
#include "util/runtime_module.hpp"

#ifndef FIBRODEM_CLI_DIR
#error "FIBRODEM_CLI_DIR (the folder of the fibrodem executable) must be defined by the build"
#endif

namespace fibrodem::python {

std::shared_ptr<PluginRegistry> shared_registry() {
  static const auto registry =
      std::make_shared<PluginRegistry>(PluginRegistry::search_path_beside(FIBRODEM_CLI_DIR));
  return registry;
}

std::mutex& registry_mutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace fibrodem::python

PYBIND11_MODULE(_core, m) {
  m.doc() = "fibrodem's core library (use the fibrodem package, not this module)";
  m.attr("version") = FIBRODEM_VERSION;
  m.attr("cli_dir") = FIBRODEM_CLI_DIR;
  // The drawing module is built beside the command line (modules/).
  fibrodem::add_module_directory(FIBRODEM_CLI_DIR);
  fibrodem::python::bind_errors(m);
  fibrodem::python::bind_scene(m);
  fibrodem::python::bind_run(m);
  fibrodem::python::bind_simulate_cell(m);
  fibrodem::python::bind_plugins(m);
  fibrodem::python::bind_study(m);
}
