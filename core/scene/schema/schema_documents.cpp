#include "scene/schema/schema_documents.hpp"

#include <stdexcept>

namespace fibrodem {

const char* schema_kind_name(SchemaKind kind) { return kind == SchemaKind::manifest ? "manifest" : "sweep"; }

SchemaKind schema_kind_named(const std::string& name) {
  if (name == "manifest") return SchemaKind::manifest;
  if (name == "sweep") return SchemaKind::sweep;
  throw std::invalid_argument("no schema named \"" + name + "\" (expected \"manifest\" or \"sweep\")");
}

// Each schema is parsed on its first use only: a run reads a manifest and
// never needs the sweep file's schema (a parse costs start-up time). Never
// destroyed: the process ends with it, where freeing its thousands of nodes
// one by one at exit cost a one-cell run about a percent of its CPU time.
const json& schema_document(SchemaKind kind) {
  if (kind == SchemaKind::manifest) {
    static const json& manifest = *new json(json::parse(schema_text(SchemaKind::manifest)));
    return manifest;
  }
  static const json& sweep = *new json(json::parse(schema_text(SchemaKind::sweep)));
  return sweep;
}

const json& resolve_schema_ref(const json& root, const json& node) {
  const json* at = &node;
  // (A bound on the hops: a cycle of references in a schema is a bug, not a hang.)
  for (int hops = 0; at->is_object() && at->contains("$ref") && hops < 32; ++hops) {
    const std::string ref = (*at)["$ref"].get<std::string>();
    const std::string prefix = "#/definitions/";
    if (ref.rfind(prefix, 0) != 0 || !root.contains("definitions") ||
        !root["definitions"].contains(ref.substr(prefix.size())))
      throw std::logic_error("schema: unresolvable $ref \"" + ref + "\"");
    at = &root["definitions"][ref.substr(prefix.size())];
  }
  return *at;
}

}  // namespace fibrodem
