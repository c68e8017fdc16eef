// fibrodem._core.Scene: a manifest, checked as the command line checks it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding.hpp"
#include "py_json.hpp"
#include "scene/scene.hpp"
#include "scene_handle.hpp"

namespace py = pybind11;

namespace fibrodem::python {

SceneHandle SceneHandle::from_file(const std::string& file) {
  SceneHandle s{read_manifest_file(file)};
  parse_scene(s.manifest);  // checks; throws ManifestError naming the path
  return s;
}

SceneHandle SceneHandle::from_dict(py::handle dict) {
  SceneHandle s{to_json(dict, "scene")};
  parse_scene(s.manifest);
  return s;
}

// --set PATH=VALUE exactly: the same parser of the assignment and the same
// checks of the whole manifest after it; the scene changes only if both pass.
void SceneHandle::set(const std::string& path, py::handle value) {
  json changed = manifest;
  apply_override(changed, path + "=" + to_json(value, "value").dump());
  parse_scene(changed);
  manifest = std::move(changed);
}

void bind_scene(py::module_& m) {
  py::class_<SceneHandle>(m, "Scene")
      .def_static("from_file", &SceneHandle::from_file, py::arg("file"))
      .def_static("from_dict", &SceneHandle::from_dict, py::arg("manifest"))
      .def("set", &SceneHandle::set, py::arg("path"), py::arg("value"))
      .def("manifest", [](const SceneHandle& s) { return to_python(s.manifest); })
      .def("copy", [](const SceneHandle& s) { return SceneHandle{s.manifest}; });
  // The type of each cell of a manifest's tissue, built as a run builds it
  // (fibrodem.read: the maps' cells; no plugin is loaded).
  m.def("tissue_cell_types", [](py::handle manifest) {
    const Scene scene = parse_scene(to_json(manifest, "manifest"));
    std::vector<std::string> types;
    for (CellType t : scene.tissue->build(scene.seed).type) types.emplace_back(cell_type_name(t));
    return types;
  });
}

}  // namespace fibrodem::python
