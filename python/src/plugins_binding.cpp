// fibrodem._core.plugins: what `fibrodem plugins --json` prints, as dicts.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding.hpp"
#include "model/model_description.hpp"
#include "py_json.hpp"

namespace py = pybind11;

namespace fibrodem::python {

void bind_plugins(py::module_& m) {
  m.def("plugins", [] {
    std::vector<std::string> errors;
    nlohmann::json models;
    {
      std::lock_guard lock(registry_mutex());
      models = describe_available_models(*shared_registry(), errors);
    }
    py::dict d;
    d["models"] = to_python(models);
    d["errors"] = errors;
    std::vector<std::string> path;
    for (const auto& p : shared_registry()->search_path()) path.push_back(p.string());
    d["search_path"] = path;
    return d;
  });
}

}  // namespace fibrodem::python
