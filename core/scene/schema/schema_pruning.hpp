// A JSON Schema cut down to what one document can meet, so that a process
// that checks a single manifest (a run) gives valijson a few kilobytes to
// parse instead of the whole manifest schema (its parse was an eighth of a
// one-cell run's CPU time).
//
// What goes: the keys of "properties" the document does not hold (a
// property's schema applies only to a member of that name, and
// "additionalProperties" judges only members the document holds, none of
// which is one of those names), annotations ("description", "title",
// "$comment", "default", "examples") and "definitions", every local "$ref"
// being replaced by (the cut-down form of) what it points to. Every other
// keyword stays, with its subschemas cut down for the values they apply to
// (the members of an object, the items of a list, the keys of an object for
// "propertyNames"; the document itself for allOf, anyOf, oneOf, not, if,
// then, else). So the document satisfies the cut-down schema exactly when it
// satisfies the whole one; a schema reached by no value becomes {}.
#pragma once

#include <optional>

#include "scene/schema/schema_documents.hpp"

namespace fibrodem {

// The schema `root` cut down for `document`; nullopt if its "$ref"s nest
// deeper than the document could explain (a cycle), where the caller uses
// the whole schema.
std::optional<json> schema_for_document(const json& root, const json& document);

}  // namespace fibrodem
