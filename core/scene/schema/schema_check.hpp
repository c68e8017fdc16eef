// Checks a manifest or a sweep file against its JSON Schema (valijson), and
// turns a failure into a ManifestError that names the JSON path of the
// offending value (dotted, [i] for list entries, as JsonReader does) and what
// the schema expects there, e.g. `tissue.width_mm: expected a number in
// [0.025, 100], got 0`.
#pragma once

#include <memory>

#include "scene/schema/schema_documents.hpp"

namespace fibrodem {

// Throws ManifestError for the first problem found (depth first, in the
// document's key order); returns if the document satisfies the schema.
void check_against_schema(SchemaKind kind, const json& document);

// A schema, whole or cut down (schema_pruning.hpp), parsed once to judge
// documents as valijson (draft 7) does; integral numbers written with a
// fraction (2.0) count as integers.
class SchemaJudge {
 public:
  explicit SchemaJudge(const json& schema);
  ~SchemaJudge();
  bool satisfied_by(const json& document) const;

 private:
  struct Parsed;
  std::unique_ptr<Parsed> parsed_;
};

// A schema node in words, for messages and the reference: "a number in
// [0, 1]", "one of \"a\", \"b\"", "a list (each: an integer >= 0)".
std::string describe_schema(const json& root, const json& node);

}  // namespace fibrodem
