// The JSON Schemas of the manifest and of the sweep file: schema/*.schema.json
// in the repository, embedded in the program at build time (CMake writes
// embedded_schemas.cpp from them), so an installed fibrodem needs no file.
#pragma once

#include <string>
#include <string_view>

#include "util/json_reader.hpp"

namespace fibrodem {

enum class SchemaKind { manifest, sweep };

// "manifest" or "sweep".
const char* schema_kind_name(SchemaKind kind);
// The kind of that name; std::invalid_argument for any other.
SchemaKind schema_kind_named(const std::string& name);

// The schema's text as in the repository (embedded_schemas.cpp).
std::string_view schema_text(SchemaKind kind);
// The schema, parsed once.
const json& schema_document(SchemaKind kind);

// The node a "$ref" (local, "#/definitions/NAME") points to, followed until
// a node without one; any other node as it is.
const json& resolve_schema_ref(const json& root, const json& node);

}  // namespace fibrodem
