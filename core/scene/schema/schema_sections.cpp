#include "scene/schema/schema_sections.hpp"

#include <algorithm>
#include <deque>

namespace fibrodem {

namespace {

class Walk {
 public:
  explicit Walk(const json& root) : root_(root) {}

  void object(const json& node, const std::string& location, const std::string& skip = "") {
    const json& s = resolve_schema_ref(root_, node);
    SchemaSection& section = section_at(location);
    if (section.description.empty()) section.description = s.value("description", std::string());
    const json& required = s.value("required", json::array());
    if (s.contains("properties")) {
      for (const auto& [key, property] : s["properties"].items()) {
        if (key == skip) continue;
        const bool is_required = std::find(required.begin(), required.end(), key) != required.end();
        add_key(section_at(location), SchemaKey{key, with_description(property), is_required});
        value(property, location.empty() ? key : location + "." + key);
      }
    } else if (s.contains("additionalProperties") && s["additionalProperties"] != false) {
      const json& each = resolve_schema_ref(root_, s["additionalProperties"]);
      if (each.is_object() && each.contains("properties")) {
        // Objects by a name from a closed list (cells.TYPE): listed once, under
        // the title of propertyNames ("TYPE").
        const json& names = s.value("propertyNames", json::object());
        const std::string name = names.value("title", std::string("*"));
        add_key(section_at(location), SchemaKey{name, with_description(s["additionalProperties"]), false});
        value(s["additionalProperties"], location + "." + name);
      } else {
        section_at(location).free_keys = true;
      }
    }
    if (s.contains("oneOf")) branches(s["oneOf"], location);
  }

  std::vector<SchemaSection> sections() && { return {sections_.begin(), sections_.end()}; }

 private:
  // A key's value: an object, a list of objects, or either (oneOf).
  void value(const json& node, const std::string& location) {
    const json& s = resolve_schema_ref(root_, node);
    const std::string type = s.value("type", std::string());
    if (type == "object") object(s, location);
    else if (type == "array" && s.contains("items") && s["items"].is_object()) value(s["items"], location + "[]");
    else if (s.contains("oneOf")) branches(s["oneOf"], location);
  }

  void branches(const json& list, const std::string& location) {
    for (const auto& branch : list) {
      const json& b = resolve_schema_ref(root_, branch);
      std::string tag_key, tag;
      if (b.contains("properties"))
        for (const auto& [key, property] : b["properties"].items())
          if (property.contains("const")) {
            tag_key = key;
            tag = "{" + key + "=" + property["const"].get<std::string>() + "}";
            break;
          }
      if (tag.empty()) value(b, location);
      else object(b, location + tag, tag_key);
    }
  }

  // The key's schema with the $ref resolved and the keywords beside it (a
  // description, a default) kept over the referenced ones.
  json with_description(const json& node) const {
    json merged = resolve_schema_ref(root_, node);
    if (!merged.is_object()) return merged;
    for (const auto& [key, value] : node.items())
      if (key != "$ref") merged[key] = value;
    return merged;
  }

  SchemaSection& section_at(const std::string& location) {
    for (auto& s : sections_)
      if (s.location == location) return s;
    sections_.push_back(SchemaSection{location, "", {}, false});
    return sections_.back();
  }

  static void add_key(SchemaSection& section, SchemaKey key) {
    for (const auto& k : section.keys)
      if (k.name == key.name) return;
    section.keys.push_back(std::move(key));
  }

  const json& root_;
  std::deque<SchemaSection> sections_;  // (a deque: references to a section stay valid while others are added)
};

}  // namespace

std::vector<SchemaSection> schema_sections(const json& root) {
  Walk walk(root);
  walk.object(root, "");
  return std::move(walk).sections();
}

}  // namespace fibrodem
