// The reference of a schema in Markdown (docs/reference/manifest.md and
// sweep_file.md are this text): one table per object, a row per key with its
// type, default, allowed values and description.
#pragma once

#include <string>

#include "scene/schema/schema_documents.hpp"

namespace fibrodem {

std::string schema_markdown(SchemaKind kind);

}  // namespace fibrodem
