#include "scene/schema/schema_pruning.hpp"

#include <array>
#include <string_view>
#include <vector>

namespace fibrodem {

namespace {

using Values = std::vector<const json*>;

// Nesting of schemas (through $ref, allOf, not, ...) past which the schema is
// taken to hold a cycle: the manifest schema nests about a dozen deep.
constexpr int kMostDepth = 200;

struct TooDeep {};

bool annotation(std::string_view key) {
  static constexpr std::array<std::string_view, 8> kDropped{"description", "title",   "$comment", "default",
                                                            "examples",    "$schema", "$id",      "definitions"};
  for (const auto dropped : kDropped)
    if (key == dropped) return true;
  return false;
}

// The children of the values of one type among `values`: the member values
// of the objects (json::value_t::object), or the items of the lists (array).
Values children_of(const Values& values, json::value_t type) {
  Values out;
  for (const json* v : values)
    if (v->type() == type)
      for (const auto& child : *v) out.push_back(&child);
  return out;
}
Values members_of(const Values& values) { return children_of(values, json::value_t::object); }
Values items_of(const Values& values) { return children_of(values, json::value_t::array); }

class Pruner {
 public:
  explicit Pruner(const json& root) : root_(root) {}

  // `node` cut down for `values` (all of the values it applies to).
  json prune(const json& node_or_ref, const Values& values, int depth) {
    if (depth > kMostDepth) throw TooDeep{};
    const json& node = resolve_schema_ref(root_, node_or_ref);
    if (!node.is_object()) return node;     // true or false
    if (values.empty()) return json::object();  // applies to nothing here
    json out = json::object();
    for (const auto& [key, sub] : node.items()) {
      if (annotation(key)) continue;
      out[key] = keyword(key, sub, values, depth);
    }
    return out;
  }

 private:
  json keyword(const std::string& key, const json& sub, const Values& values, int depth) {
    if (key == "properties") return properties(sub, values, depth);
    if (key == "allOf" || key == "anyOf" || key == "oneOf") {
      json branches = json::array();
      for (const auto& branch : sub) branches.push_back(prune(branch, values, depth + 1));
      return branches;
    }
    if (key == "not" || key == "if" || key == "then" || key == "else") return prune(sub, values, depth + 1);
    if (key == "additionalProperties") return prune(sub, members_of(values), depth + 1);
    if (key == "patternProperties") {
      json patterns = json::object();
      const Values members = members_of(values);  // (a superset of each pattern's: still exact)
      for (const auto& [pattern, schema] : sub.items()) patterns[pattern] = prune(schema, members, depth + 1);
      return patterns;
    }
    if (key == "propertyNames") return property_names(sub, values, depth);
    if (key == "items" && sub.is_array()) return tuple_items(sub, values, depth);
    if (key == "items" || key == "additionalItems" || key == "contains")
      return prune(sub, items_of(values), depth + 1);
    if (key == "dependencies") {
      json out = json::object();
      for (const auto& [name, dependency] : sub.items())
        out[name] = dependency.is_array() ? dependency : prune(dependency, values, depth + 1);
      return out;
    }
    return sub;  // an assertion (type, enum, minimum, required, pattern, ...) as it is
  }

  json properties(const json& sub, const Values& values, int depth) {
    json out = json::object();
    for (const auto& [name, schema] : sub.items()) {
      Values named;
      for (const json* v : values)
        if (v->is_object())
          if (const auto at = v->find(name); at != v->end()) named.push_back(&*at);
      if (!named.empty()) out[name] = prune(schema, named, depth + 1);
    }
    return out;
  }

  json property_names(const json& sub, const Values& values, int depth) {
    std::vector<json> names;
    for (const json* v : values)
      if (v->is_object())
        for (const auto& [name, member] : v->items()) names.emplace_back(name);
    Values named;
    for (const auto& name : names) named.push_back(&name);
    return prune(sub, named, depth + 1);
  }

  json tuple_items(const json& sub, const Values& values, int depth) {
    json out = json::array();
    for (std::size_t i = 0; i < sub.size(); ++i) {
      Values at;
      for (const json* v : values)
        if (v->is_array() && v->size() > i) at.push_back(&(*v)[i]);
      out.push_back(prune(sub[i], at, depth + 1));
    }
    return out;
  }

  const json& root_;
};

}  // namespace

std::optional<json> schema_for_document(const json& root, const json& document) {
  try {
    return Pruner(root).prune(root, {&document}, 0);
  } catch (const TooDeep&) {
    return std::nullopt;
  }
}

}  // namespace fibrodem
