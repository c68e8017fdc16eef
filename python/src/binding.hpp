// The pieces of the _core extension module (fibrodem's Python layer calls
// these; the public API and its docstrings are in fibrodem/__init__.py).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>

#include "model/plugin_registry.hpp"

namespace fibrodem::python {

// One registry for the process, searching where the command line does
// (FIBRODEM_PLUGIN_PATH, then beside the build's `fibrodem` executable), so
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
