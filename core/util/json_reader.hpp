// Reads one JSON object of a manifest, value by value, checking types and
// ranges, and remembering which keys were read so that finish() can reject
// the unknown ones. Every error names the dotted JSON path of the value.
#pragma once

#include <nlohmann/json.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "util/manifest_error.hpp"

namespace fibrodem {

using json = nlohmann::json;

std::string describe_json(const json& value);  // short text of a value for messages
std::string join_path(const std::string& parent, const std::string& key);
std::string index_path(const std::string& parent, std::size_t index);

class JsonReader {
 public:
  JsonReader(const json& object, std::string path);

  const std::string& path() const { return path_; }
  std::string path_of(const std::string& key) const { return join_path(path_, key); }
  bool has(const std::string& key) const { return object_.contains(key); }

  // Numbers within [min, max]; without a default the key is required.
  double number(const std::string& key, std::optional<double> fallback, double min, double max);
  long long integer(const std::string& key, std::optional<long long> fallback, long long min,
                    long long max);
  bool boolean(const std::string& key, std::optional<bool> fallback);
  // A string; if `allowed` is non-empty it must be one of them.
  std::string text(const std::string& key, std::optional<std::string> fallback,
                   const std::vector<std::string>& allowed = {});
  std::vector<std::string> text_list(const std::string& key, std::vector<std::string> fallback);
  // Any value, marked as read (nullptr-like empty json if absent).
  const json& raw(const std::string& key);
  JsonReader object(const std::string& key);

  // Throws for the first key that was never read.
  void finish() const;

 private:
  const json& require(const std::string& key);
  void mark_read(const std::string& key);

  const json& object_;
  std::string path_;
  std::set<std::string> read_;
};

// A JSON list of cell indices (integers >= 0), or a ManifestError at
// path[i] naming the first entry that is not one.
std::vector<int> read_cell_indices(const json& list, const std::string& path);

// Records every (JSON path of an object, key) that a JsonReader on this
// thread reads (with or without a value in the manifest) while it lives, so
// that a test can compare the keys the code reads with those the schema
// lists (tests/scene/test_manifest_schema.cpp). Logs nest: the newest records.
class KeyReadLog {
 public:
  KeyReadLog();
  ~KeyReadLog();
  KeyReadLog(const KeyReadLog&) = delete;
  KeyReadLog& operator=(const KeyReadLog&) = delete;

  void add(const std::string& object_path, const std::string& key) { keys_.emplace(object_path, key); }
  const std::set<std::pair<std::string, std::string>>& keys() const { return keys_; }

  // A number's rule as the reader applied it: its default (none: required)
  // and range, so that a test can hold them to the schema's value by value.
  struct NumberRule {
    std::optional<double> fallback;
    double min = 0, max = 0;
  };
  void add_number(const std::string& object_path, const std::string& key, NumberRule rule) {
    numbers_[{object_path, key}] = rule;
  }
  const std::map<std::pair<std::string, std::string>, NumberRule>& numbers() const { return numbers_; }

 private:
  std::set<std::pair<std::string, std::string>> keys_;
  std::map<std::pair<std::string, std::string>, NumberRule> numbers_;
  KeyReadLog* previous_;
};

}  // namespace fibrodem
