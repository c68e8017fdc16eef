#include "util/json_reader.hpp"
#include "util/number_text.hpp"

#include <cmath>

namespace fibrodem {

namespace {
const json kAbsent;
thread_local KeyReadLog* active_key_log = nullptr;

std::string range_text(double min, double max) {
  if (min > -1e300 && max < 1e300) return " in [" + significant_digits(min, 12) + ", " + significant_digits(max, 12) + "]";
  if (min > -1e300) return " >= " + significant_digits(min, 12);
  if (max < 1e300) return " <= " + significant_digits(max, 12);
  return "";
}
}  // namespace

std::string describe_json(const json& value) {
  // (Invalid UTF-8 in a string is shown replaced, not thrown: found by fuzzing.)
  std::string s = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string join_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string index_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

JsonReader::JsonReader(const json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object())
    throw ManifestError(path_, "expected an object, got " + describe_json(object_));
}

KeyReadLog::KeyReadLog() : previous_(active_key_log) { active_key_log = this; }
KeyReadLog::~KeyReadLog() { active_key_log = previous_; }

void JsonReader::mark_read(const std::string& key) {
  read_.insert(key);
  if (active_key_log) active_key_log->add(path_, key);
}

const json& JsonReader::require(const std::string& key) {
  mark_read(key);
  if (!object_.contains(key)) throw ManifestError(path_of(key), "required value is missing");
  return object_.at(key);
}

double JsonReader::number(const std::string& key, std::optional<double> fallback, double min,
                          double max) {
  if (active_key_log) active_key_log->add_number(path_, key, {fallback, min, max});
  if (!has(key) && fallback) {
    mark_read(key);
    return *fallback;
  }
  const json& v = require(key);
  if (!v.is_number())
    throw ManifestError(path_of(key), "expected a number" + range_text(min, max) + ", got " +
                                          describe_json(v));
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < min || x > max)
    throw ManifestError(path_of(key), "expected a number" + range_text(min, max) + ", got " +
                                          describe_json(v));
  return x;
}

long long JsonReader::integer(const std::string& key, std::optional<long long> fallback,
                              long long min, long long max) {
  if (active_key_log) {
    std::optional<double> fallback_value;
    if (fallback) fallback_value = static_cast<double>(*fallback);
    active_key_log->add_number(path_, key, {fallback_value, static_cast<double>(min), static_cast<double>(max)});
  }
  if (!has(key) && fallback) {
    mark_read(key);
    return *fallback;
  }
  const json& v = require(key);
  const std::string expected =
      "expected an integer" + range_text(static_cast<double>(min), static_cast<double>(max));
  if (!v.is_number_integer() && !(v.is_number_float() && std::floor(v.get<double>()) == v.get<double>()))
    throw ManifestError(path_of(key), expected + ", got " + describe_json(v));
  const double x = v.get<double>();
  if (x < static_cast<double>(min) || x > static_cast<double>(max))
    throw ManifestError(path_of(key), expected + ", got " + describe_json(v));
  return static_cast<long long>(x);
}

bool JsonReader::boolean(const std::string& key, std::optional<bool> fallback) {
  if (!has(key) && fallback) {
    mark_read(key);
    return *fallback;
  }
  const json& v = require(key);
  if (!v.is_boolean())
    throw ManifestError(path_of(key), "expected true or false, got " + describe_json(v));
  return v.get<bool>();
}

std::string JsonReader::text(const std::string& key, std::optional<std::string> fallback,
                             const std::vector<std::string>& allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
  if (!has(key) && fallback) {
    mark_read(key);
    return *fallback;
  }
  const json& v = require(key);
  if (!v.is_string())
    throw ManifestError(path_of(key), (allowed.empty() ? "expected a string" : "expected one of " + list) +
                                          ", got " + describe_json(v));
  std::string s = v.get<std::string>();
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end())
    throw ManifestError(path_of(key), "expected one of " + list + ", got " + describe_json(v));
  return s;
}

std::vector<std::string> JsonReader::text_list(const std::string& key,
                                               std::vector<std::string> fallback) {
  mark_read(key);
  if (!has(key)) return fallback;
  const json& v = object_.at(key);
  if (!v.is_array())
    throw ManifestError(path_of(key), "expected a list of strings, got " + describe_json(v));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_string())
      throw ManifestError(index_path(path_of(key), i), "expected a string, got " + describe_json(v[i]));
    out.push_back(v[i].get<std::string>());
  }
  return out;
}

const json& JsonReader::raw(const std::string& key) {
  mark_read(key);
  return has(key) ? object_.at(key) : kAbsent;
}

JsonReader JsonReader::object(const std::string& key) {
  return JsonReader(require(key), path_of(key));
}

void JsonReader::finish() const {
  for (const auto& [key, value] : object_.items()) {
    if (read_.count(key) == 0) {
      std::string known;
      for (const auto& k : read_) known += (known.empty() ? "" : ", ") + k;
      throw ManifestError(path_of(key), "unknown key (known here: " + known + ")");
    }
  }
}

std::vector<int> read_cell_indices(const json& list, const std::string& path) {
  std::vector<int> cells;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_number_integer() || list[i].get<long long>() < 0)
      throw ManifestError(index_path(path, i),
                          "expected a cell index (integer >= 0), got " + describe_json(list[i]));
    cells.push_back(list[i].get<int>());
  }
  return cells;
}

}  // namespace fibrodem
