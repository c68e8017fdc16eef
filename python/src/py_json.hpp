// Python objects <-> nlohmann::json, walked directly (no text round trip):
// manifests given as dicts, parameters, and summary.json as a dict.
#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

namespace fibrodem::python {

// None, bool, int, float, str, list/tuple and dict with str keys; anything else
// raises TypeError naming `what` and the place inside it (e.g. "scene['cells']").
nlohmann::json to_json(pybind11::handle value, const std::string& what);
pybind11::object to_python(const nlohmann::json& value);

}  // namespace fibrodem::python
