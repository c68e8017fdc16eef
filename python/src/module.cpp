// fibrodem._core: the binding of the core library. Nothing here simulates:
// every call goes to the same core code as the command line.
#include <pybind11/pybind11.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <system_error>

#include "binding.hpp"
#include "util/runtime_module.hpp"

#ifndef FIBRODEM_CLI_DIR
#error "FIBRODEM_CLI_DIR (the folder of the fibrodem executable) must be defined by the build"
#endif

namespace fibrodem::python {

const std::filesystem::path& cli_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path bundled = boost::dll::this_line_location().parent_path() / "bin";
    std::error_code ec;
    return std::filesystem::is_directory(bundled, ec) ? bundled : std::filesystem::path(FIBRODEM_CLI_DIR);
  }();
  return dir;
}

std::shared_ptr<PluginRegistry> shared_registry() {
  static const auto registry = std::make_shared<PluginRegistry>(PluginRegistry::search_path_beside(cli_dir()));
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
  m.attr("cli_dir") = fibrodem::python::cli_dir().string();
  // The drawing module is built beside the command line (modules/).
  fibrodem::add_module_directory(fibrodem::python::cli_dir());
  fibrodem::python::bind_errors(m);
  fibrodem::python::bind_scene(m);
  fibrodem::python::bind_run(m);
  fibrodem::python::bind_simulate_cell(m);
  fibrodem::python::bind_plugins(m);
  fibrodem::python::bind_study(m);
}
