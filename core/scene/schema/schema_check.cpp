#include "scene/schema/schema_check.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <set>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include "scene/schema/schema_pruning.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

namespace {

struct Problem {
  std::string path;
  std::string what;
};

std::unique_ptr<valijson::Schema> parse_schema(const json& document) {
  auto schema = std::make_unique<valijson::Schema>();
  valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
  valijson::adapters::NlohmannJsonAdapter adapter(document);
  parser.populateSchema(adapter, *schema);
  return schema;
}

bool valid(const valijson::Schema& schema, const json& instance) {
  // One validation at a time: a `pattern` compiles a std::regex, which fills
  // the locale's shared ctype cache unsynchronised, and a sweep's worker
  // threads read scenes at once (ThreadSanitizer reports it). Validation is
  // a small part of reading a manifest.
  static std::mutex one_at_a_time;
  const std::lock_guard<std::mutex> lock(one_at_a_time);
  valijson::Validator validator;  // strict types: 1.5 is no integer, "1" no number
  valijson::adapters::NlohmannJsonAdapter target(instance);
  return validator.validate(schema, target, nullptr);
}

// Whether `instance` satisfies the sub-schema `node` of `root` (parsed on its
// own with root's definitions, so that its $refs resolve). Only used to find
// where a document that failed the whole schema goes wrong.
bool valid_against(const json& root, const json& node, const json& instance) {
  if (node.is_boolean()) return node.get<bool>();
  json document = node;
  if (root.contains("definitions")) document["definitions"] = root["definitions"];
  return valid(*parse_schema(document), instance);
}

bool type_accepts(const json& type, const json& instance) {
  if (type.is_array()) {
    for (const auto& t : type)
      if (type_accepts(t, instance)) return true;
    return false;
  }
  const std::string t = type.get<std::string>();
  return (t == "object" && instance.is_object()) || (t == "array" && instance.is_array()) ||
         (t == "string" && instance.is_string()) || (t == "boolean" && instance.is_boolean()) ||
         (t == "number" && instance.is_number()) || (t == "integer" && instance.is_number_integer()) ||
         (t == "null" && instance.is_null());
}

// Whether a oneOf branch is the one meant for `instance`: its type fits and
// its constant properties (a discriminator such as tissue.builder) match.
bool branch_fits(const json& branch, const json& instance) {
  if (branch.contains("type") && !type_accepts(branch["type"], instance)) return false;
  if (branch.contains("enum") || branch.contains("const")) {
    if (!instance.is_string() && !instance.is_number() && !instance.is_boolean()) return false;
  }
  if (branch.contains("properties") && instance.is_object())
    for (const auto& [key, property] : branch["properties"].items())
      if (property.contains("const") && instance.contains(key) && instance[key] != property["const"]) return false;
  return true;
}

// The schemas that apply to `instance` at `node`: the node, its allOf, the
// then or else of its if, and its oneOf branch meant for the instance.
void applicable(const json& root, const json& node, const json& instance, std::vector<const json*>& out) {
  const json& s = resolve_schema_ref(root, node);
  if (!s.is_object()) return;
  out.push_back(&s);
  if (s.contains("allOf"))
    for (const auto& part : s["allOf"]) applicable(root, part, instance, out);
  if (s.contains("if")) {
    const char* branch = valid_against(root, s["if"], instance) ? "then" : "else";
    if (s.contains(branch)) applicable(root, s[branch], instance, out);
  }
  if (s.contains("oneOf")) {
    std::vector<const json*> fits;
    for (const auto& branch : s["oneOf"])
      if (branch_fits(resolve_schema_ref(root, branch), instance)) fits.push_back(&branch);
    if (fits.size() == 1) applicable(root, *fits[0], instance, out);
  }
}

std::string range_text(const json& s) {
  const bool lo = s.contains("minimum"), hi = s.contains("maximum");
  if (lo && hi) return " in [" + significant_digits(s["minimum"].get<double>(), 12) + ", " + significant_digits(s["maximum"].get<double>(), 12) + "]";
  if (lo) return " >= " + significant_digits(s["minimum"].get<double>(), 12);
  if (hi) return " <= " + significant_digits(s["maximum"].get<double>(), 12);
  return "";
}

std::optional<Problem> find_problem(const json& root, const json& node, const json& instance, const std::string& path);

std::optional<Problem> object_problem(const json& root, const std::vector<const json*>& schemas, const json& instance,
                                      const std::string& path) {
  std::set<std::string> known;
  bool closed = false;
  for (const json* s : schemas) {
    for (const auto& name : s->value("required", json::array()))
      if (!instance.contains(name.get<std::string>()))
        return Problem{join_path(path, name.get<std::string>()), "required value is missing"};
    if (s->contains("properties"))
      for (const auto& [key, value] : (*s)["properties"].items()) known.insert(key);
    if (s->contains("additionalProperties") && (*s)["additionalProperties"] == false) closed = true;
  }
  for (const auto& [key, value] : instance.items()) {
    const std::string key_path = join_path(path, key);
    if (closed && known.count(key) == 0) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      return Problem{key_path, "unknown key (known here: " + list + ")"};
    }
    for (const json* s : schemas) {
      const json* child = nullptr;
      if (s->contains("properties") && (*s)["properties"].contains(key)) child = &(*s)["properties"][key];
      else if (s->contains("additionalProperties") && (*s)["additionalProperties"].is_object())
        child = &(*s)["additionalProperties"];
      if (child)
        if (auto p = find_problem(root, *child, value, key_path)) return p;
      if (s->contains("propertyNames") && !valid_against(root, (*s)["propertyNames"], json(key))) {
        const json& names = resolve_schema_ref(root, (*s)["propertyNames"]);
        if (names.contains("not"))
          return Problem{key_path, "not allowed here" + (s->contains("$comment") ? ": " + (*s)["$comment"].get<std::string>() : "")};
        return Problem{key_path, "expected a key that is " + describe_schema(root, names)};
      }
    }
  }
  return std::nullopt;
}

std::optional<Problem> find_problem(const json& root, const json& node, const json& instance, const std::string& path) {
  if (valid_against(root, node, instance)) return std::nullopt;
  std::vector<const json*> schemas;
  applicable(root, node, instance, schemas);
  if (instance.is_object()) {
    if (auto p = object_problem(root, schemas, instance, path)) return p;
  } else if (instance.is_array()) {
    for (const json* s : schemas)
      if (s->contains("items") && (*s)["items"].is_object())
        for (std::size_t i = 0; i < instance.size(); ++i)
          if (auto p = find_problem(root, (*s)["items"], instance[i], index_path(path, i))) return p;
  }
  return Problem{path, "expected " + describe_schema(root, node) + ", got " + describe_json(instance)};
}

}  // namespace

std::string describe_schema(const json& root, const json& node) {
  const json& s = resolve_schema_ref(root, node);
  if (s.is_boolean()) return s.get<bool>() ? "any value" : "no value";
  if (s.contains("const")) return describe_json(s["const"]);
  if (s.contains("enum")) {
    std::string list;
    for (const auto& v : s["enum"]) list += (list.empty() ? "" : ", ") + describe_json(v);
    return s["enum"].size() == 1 ? list : "one of " + list;
  }
  if (s.contains("oneOf")) {
    std::vector<std::string> kinds;  // (branches told apart by a constant key read alike: said once)
    for (const auto& branch : s["oneOf"]) {
      const std::string kind = describe_schema(root, branch);
      if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) kinds.push_back(kind);
    }
    std::string list;
    for (const auto& kind : kinds) list += (list.empty() ? "" : " or ") + kind;
    return list;
  }
  const std::string type = s.contains("type") && s["type"].is_string() ? s["type"].get<std::string>() : "";
  if (type == "integer") return "an integer" + range_text(s);
  if (type == "number") return "a number" + range_text(s);
  if (type == "boolean") return "true or false";
  if (type == "string") {
    std::string text = s.value("minLength", 0) > 0 ? "a non-empty string" : "a string";
    if (s.contains("pattern")) text += " matching " + s["pattern"].get<std::string>();
    return text;
  }
  if (type == "array") {
    std::string text = "a list";
    const bool lo = s.contains("minItems"), hi = s.contains("maxItems");
    if (lo && hi && s["minItems"] == s["maxItems"]) text += " of " + s["minItems"].dump();
    else if (lo && s["minItems"].get<int>() > 0) text += " of at least " + s["minItems"].dump();
    if (s.contains("items") && s["items"].is_object() && !resolve_schema_ref(root, s["items"]).empty())
      text += " (each: " + describe_schema(root, s["items"]) + ")";
    return text;
  }
  if (type == "object") {
    const json& more = s.value("additionalProperties", json(true));
    if (!s.contains("properties") && more != false) {
      const std::string keys = s.contains("propertyNames") ? describe_schema(root, s["propertyNames"]) : "a name";
      return "an object (each key: " + keys + "; each value: " + describe_schema(root, more) + ")";
    }
    return "an object";
  }
  return "a value";
}

namespace {

// JSON Schema (draft 6 on) counts 2.0 as an integer, as JsonReader does;
// valijson counts only numbers written without a fraction: so those are
// given to it as integers.
json integral_numbers_as_integers(const json& value) {
  if (value.is_number_float()) {
    const double x = value.get<double>();
    if (std::isfinite(x) && std::floor(x) == x && std::fabs(x) < 9.2e18) return static_cast<long long>(x);
    return value;
  }
  if (!value.is_structured()) return value;
  json out = value;
  for (auto& item : out) item = integral_numbers_as_integers(item);
  return out;
}

// The valijson form of a whole schema, built on its first use only (as
// schema_document: a run never needs the sweep file's).
const valijson::Schema& parsed_schema(SchemaKind kind) {
  if (kind == SchemaKind::manifest) {
    static const std::unique_ptr<valijson::Schema> manifest = parse_schema(schema_document(SchemaKind::manifest));
    return *manifest;
  }
  static const std::unique_ptr<valijson::Schema> sweep = parse_schema(schema_document(SchemaKind::sweep));
  return *sweep;
}

// Whether `document` satisfies the schema. The first document of a kind is
// checked against the schema cut down to it (schema_pruning.hpp): a run
// checks one manifest, and valijson's parse of the whole schema cost it more
// than the check. A process that checks more (a sweep, a study, the tests)
// parses the whole schema once, on its second document, and keeps it.
bool satisfies_schema(SchemaKind kind, const json& document) {
  static std::atomic<bool> checked_one[2] = {false, false};
  if (!checked_one[static_cast<int>(kind)].exchange(true))
    if (const auto cut = schema_for_document(schema_document(kind), document))
      return valid(*parse_schema(*cut), document);
  return valid(parsed_schema(kind), document);
}

}  // namespace

struct SchemaJudge::Parsed {
  std::unique_ptr<valijson::Schema> schema;
};
SchemaJudge::SchemaJudge(const json& schema) : parsed_(std::make_unique<Parsed>(Parsed{parse_schema(schema)})) {}
SchemaJudge::~SchemaJudge() = default;
bool SchemaJudge::satisfied_by(const json& document) const {
  return valid(*parsed_->schema, integral_numbers_as_integers(document));
}

void check_against_schema(SchemaKind kind, const json& given) {
  const json document = integral_numbers_as_integers(given);
  if (satisfies_schema(kind, document)) return;
  const json& root = schema_document(kind);
  if (auto p = find_problem(root, root, document, "")) throw ManifestError(p->path, p->what + " (" + schema_kind_name(kind) + " schema)");
  throw ManifestError("", std::string("does not satisfy the ") + schema_kind_name(kind) + " schema");
}

}  // namespace fibrodem
