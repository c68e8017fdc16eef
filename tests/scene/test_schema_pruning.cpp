// The schema cut down to one document (scene/schema/schema_pruning.hpp),
// against the reference of the whole schema: valijson's verdict on the
// document must be the same under both, for the example manifests and sweep
// files and for many broken variants of them.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "scene/schema/schema_check.hpp"
#include "scene/schema/schema_pruning.hpp"
#include "scene/scene.hpp"
#include "support/example_files.hpp"

using namespace fibrodem;

namespace {

namespace fs = std::filesystem;
const fs::path kSource = FIBRODEM_SOURCE_DIR;

// The document and variants of it, each with one change at one place: an
// unknown key added to an object, a key removed, a value replaced by one of
// the wrong type or far out of any range either way, a list emptied.
void variants(const json& document, json& value, const std::function<void(const json&)>& each) {
  if (value.is_object()) {
    value["zz_unknown_key"] = 1;
    each(document);
    value.erase("zz_unknown_key");
    std::vector<std::string> keys;
    for (const auto& [key, member] : value.items()) keys.push_back(key);
    for (const auto& key : keys) {
      json kept = value[key];
      value.erase(key);
      each(document);
      value[key] = kept;
      variants(document, value[key], each);
    }
  } else if (value.is_array()) {
    json kept = value;
    value = json::array();
    each(document);
    value = kept;
    for (auto& item : value) variants(document, item, each);
  } else {
    const json kept = value;
    for (const json& other : {json("x"), json(-1e12), json(1e12)}) {
      value = other;
      each(document);
    }
    value = kept;
  }
}

}  // namespace

TEST_CASE("a schema cut down to a document judges it as the whole schema does") {
  const SchemaJudge whole_manifest(schema_document(SchemaKind::manifest)), whole_sweep(schema_document(SchemaKind::sweep));
  int valid = 0, invalid = 0;
  for (const auto& file : testing::example_files()) {
    CAPTURE(file.string());
    json document = read_manifest_file(file.string());
    const SchemaKind kind = document.contains("fibrodem_sweep") ? SchemaKind::sweep : SchemaKind::manifest;
    const json& whole = schema_document(kind);
    const SchemaJudge& reference = kind == SchemaKind::sweep ? whole_sweep : whole_manifest;
    CHECK(reference.satisfied_by(document));
    variants(document, document, [&](const json& variant) {
      const std::optional<json> cut = schema_for_document(whole, variant);
      REQUIRE(cut.has_value());
      const bool expected = reference.satisfied_by(variant);
      CAPTURE(variant.dump());
      CHECK(SchemaJudge(*cut).satisfied_by(variant) == expected);
      ++(expected ? valid : invalid);
    });
  }
  // Floors, so that a walk that finds little cannot pass: the 30 example
  // files give thousands of variants, most of them broken, some not (an
  // optional key removed, a number still in range).
  CHECK(invalid >= 2000);
  CHECK(valid >= 200);
}

TEST_CASE("the manifest schema cut down to a one-cell manifest is a small part of it, with no reference left") {
  const json& whole = schema_document(SchemaKind::manifest);
  const json manifest = read_manifest_file((kSource / "examples" / "single_cell_colman_ni2017.json").string());
  const std::optional<json> cut = schema_for_document(whole, manifest);
  REQUIRE(cut.has_value());
  const std::string text = cut->dump();
  // The whole schema is 36 kB written compactly; what the example's keys reach
  // (tissue, cells, stimulus, solver, output without its descriptions) is
  // about 4 kB.
  CHECK(text.size() * 5 < whole.dump().size());
  CHECK(text.find("$ref") == std::string::npos);
  CHECK(text.find("description") == std::string::npos);
  CHECK(!cut->contains("definitions"));
  // Sections the manifest does not hold are gone; those it holds stay closed.
  CHECK(!(*cut)["properties"].contains("mechanics"));
  CHECK((*cut)["properties"].contains("solver"));
  CHECK((*cut)["additionalProperties"] == false);
}

TEST_CASE("a schema whose references form a cycle is not cut down") {
  const json cyclic = {{"definitions", {{"a", {{"$ref", "#/definitions/b"}}}, {"b", {{"allOf", {{{"$ref", "#/definitions/a"}}}}}}}},
                       {"$ref", "#/definitions/b"}};
  CHECK(!schema_for_document(cyclic, json::object()).has_value());
}
