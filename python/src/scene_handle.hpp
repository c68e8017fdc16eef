// A manifest held by Python: valid as far as parse_scene can tell (what only
// the plugins and the built tissue can check is checked when it runs).
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "util/json_reader.hpp"

namespace fibrodem::python {

struct SceneHandle {
  json manifest;

  static SceneHandle from_file(const std::string& file);
  static SceneHandle from_dict(pybind11::handle dict);
  void set(const std::string& path, pybind11::handle value);
};

}  // namespace fibrodem::python
