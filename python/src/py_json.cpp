#include "py_json.hpp"

#include <pybind11/stl.h>

namespace py = pybind11;

namespace fibrodem::python {

using json = nlohmann::json;

json to_json(py::handle value, const std::string& what) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<long long>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    json object = json::object();
    for (auto item : py::reinterpret_borrow<py::dict>(value)) {
      if (!py::isinstance<py::str>(item.first))
        throw py::type_error(what + " has a key " + py::repr(item.first).cast<std::string>() +
                             " that is not a str (JSON objects have string keys)");
      const auto key = item.first.cast<std::string>();
      object[key] = to_json(item.second, what + "['" + key + "']");
    }
    return object;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    json array = json::array();
    std::size_t i = 0;
    for (auto item : value) array.push_back(to_json(item, what + "[" + std::to_string(i++) + "]"));
    return array;
  }
  // numpy scalars (np.int64 is no int, np.float32 no float)
  if (py::hasattr(value, "__index__"))
    return py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())).cast<long long>();
  if (py::hasattr(value, "__float__"))
    return py::reinterpret_steal<py::object>(PyNumber_Float(value.ptr())).cast<double>();
  throw py::type_error(what + " must be JSON-like (None, bool, int, float, str, list, dict), not " +
                       std::string(py::str(value.get_type().attr("__name__"))));
}

py::object to_python(const json& value) {
  switch (value.type()) {
    case json::value_t::null: return py::none();
    case json::value_t::boolean: return py::bool_(value.get<bool>());
    case json::value_t::number_integer: return py::int_(value.get<long long>());
    case json::value_t::number_unsigned: return py::int_(value.get<unsigned long long>());
    case json::value_t::number_float: return py::float_(value.get<double>());
    case json::value_t::string: return py::str(value.get_ref<const std::string&>());
    case json::value_t::array: {
      py::list list;
      for (const auto& item : value) list.append(to_python(item));
      return list;
    }
    case json::value_t::object: {
      py::dict dict;
      for (const auto& [key, item] : value.items()) dict[py::str(key)] = to_python(item);
      return dict;
    }
    default: return py::none();  // binary and discarded values do not occur in manifests
  }
}

}  // namespace fibrodem::python
