// The keys a schema lists, object by object: the walk behind the generated
// reference (schema_markdown.hpp) and behind the test that the code reads
// exactly the keys the schema lists (tests/scene/test_manifest_schema.cpp).
#pragma once

#include <string>
#include <vector>

#include "scene/schema/schema_documents.hpp"

namespace fibrodem {

struct SchemaKey {
  std::string name;
  json schema;  // the key's schema, its $ref resolved, with the description beside the $ref kept
  bool required = false;
};

// One object of the document. `location` is its JSON path with list indices
// as [] ("stimulus[].target") and, for a oneOf branch told apart by a
// constant key, that key's value in braces ("tissue{builder=strand}"; the
// constant key itself is listed at "tissue").
struct SchemaSection {
  std::string location;
  std::string description;
  std::vector<SchemaKey> keys;
  bool free_keys = false;  // its keys are names chosen by the user or a plugin (parameters, grid paths)
};

std::vector<SchemaSection> schema_sections(const json& root);

}  // namespace fibrodem
