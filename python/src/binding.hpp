// The pieces of the _core extension module (fibrodem's Python layer calls
// these; the public API and its docstrings are in fibrodem/__init__.py).
#pragma once

#include <pybind11/pybind11.h>

#include <filesystem>
#include <memory>
#include <mutex>

#include "model/plugin_registry.hpp"

namespace fibrodem::python {

// The folder of the `fibrodem` command line this module runs beside, where
// its plugins and run-time modules are: <package>/bin in an installed package
// (setup.py puts them there), else the build's (FIBRODEM_CLI_DIR).
const std::filesystem::path& cli_dir();

// One registry for the process, searching where the command line does
// (FIBRODEM_PLUGIN_PATH, then beside cli_dir()'s `fibrodem` executable), so
// each plugin is loaded and hashed once. Hold registry_mutex() while using it.
std::shared_ptr<PluginRegistry> shared_registry();
std::mutex& registry_mutex();

void bind_errors(pybind11::module_& m);
void bind_scene(pybind11::module_& m);
void bind_run(pybind11::module_& m);
void bind_simulate_cell(pybind11::module_& m);
void bind_plugins(pybind11::module_& m);
void bind_study(pybind11::module_& m);

}  // namespace fibrodem::python
