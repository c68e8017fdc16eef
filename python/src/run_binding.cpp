// fibrodem._core.run: a scene run in memory (or into an output folder, as
// `fibrodem run --out` writes it).
#include <pybind11/pybind11.h>

#include "binding.hpp"
#include "guarded_run.hpp"
#include "run_result.hpp"
#include "scene/scene.hpp"
#include "scene_handle.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {

// out empty: nothing is written (the manifest's output.dir is ignored);
// else the folder, refused as the command line refuses it unless overwrite.
py::dict run_scene(const SceneHandle& handle, const std::string& out, bool overwrite, py::object progress,
                   bool catch_sigint) {
  Scene scene = parse_scene(handle.manifest);
  scene.output.dir = out;
  scene.output.overwrite = overwrite;
  RunOptions options;
  auto raised = std::make_shared<std::exception_ptr>();
  options.on_progress = progress_callback(std::move(progress), raised);
  RunOutcome outcome = guarded_run(scene, std::move(options), catch_sigint);
  if (*raised) std::rethrow_exception(*raised);
  py::dict result = collect_result(*outcome.simulation, true);
  result["status"] = outcome.status;
  result["message"] = outcome.message;
  result["out_dir"] = out.empty() ? py::object(py::none()) : py::object(py::str(out));
  return result;
}

}  // namespace

void bind_run(py::module_& m) {
  m.def("run", &run_scene, py::arg("scene"), py::arg("out"), py::arg("overwrite"), py::arg("progress"),
        py::arg("catch_sigint"));
}

}  // namespace fibrodem::python
