// The core's errors as the package's Python exceptions (fibrodem/_errors.py):
// ManifestError (path, expected) and PluginError.
#include <pybind11/pybind11.h>

#include "binding.hpp"
#include "util/manifest_error.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {

void raise(const char* name, py::tuple args) {
  py::object cls = py::module_::import("fibrodem._errors").attr(name);
  py::object error = cls(*args);
  PyErr_SetObject(cls.ptr(), error.ptr());
}

}  // namespace

void bind_errors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ManifestError& e) {
      raise("ManifestError", py::make_tuple(e.what(), e.path(), e.detail()));
    } catch (const PluginError& e) {
      raise("PluginError", py::make_tuple(e.what()));
    }
  });
}

}  // namespace fibrodem::python
