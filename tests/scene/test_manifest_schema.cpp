// The manifest and the sweep file are described once, by the JSON Schemas in
// schema/: every example validates, the code reads exactly the keys the
// schemas list (no more, no fewer), schema errors name the JSON path and what
// was expected, and the references in docs/reference/ are what the generator
// writes from the schemas now.
#include <doctest/doctest.h>

#include <fstream>

#include <regex>

#include "integrate/integrator.hpp"
#include "io/csv_writer.hpp"
#include "scene/schema/schema_check.hpp"
#include "scene/schema/schema_markdown.hpp"
#include "scene/schema/schema_sections.hpp"
#include "scene/sweep_file.hpp"
#include "support/example_files.hpp"
#include "support/scenes.hpp"
#include "tissue/tissue_builder.hpp"

using namespace fibrodem;

namespace {

namespace fs = std::filesystem;
using KeySet = std::set<std::pair<std::string, std::string>>;

const fs::path kSource = FIBRODEM_SOURCE_DIR;

// (location, key) of every key the schema lists, and the locations whose
// keys are free names (parameters, grid paths), in schema_sections' terms.
KeySet schema_keys(SchemaKind kind, std::set<std::string>* free_locations) {
  KeySet keys;
  for (const auto& section : schema_sections(schema_document(kind))) {
    if (section.free_keys) free_locations->insert(section.location);
    for (const auto& key : section.keys) keys.emplace(section.location, key.name);
  }
  return keys;
}

// (location, key) of a key JsonReader read, in schema_sections' terms: list
// indices as [], a cell type's object as cells.TYPE, the tissue's keys under
// its builder's branch.
std::pair<std::string, std::string> schema_location(const std::string& reader_path, std::string key,
                                                    const json& manifest) {
  std::string location = std::regex_replace(reader_path, std::regex(R"(\[\d+\])"), "[]");
  location = std::regex_replace(location, std::regex(R"(^cells\.(myocyte|fibroblast)\b)"), "cells.TYPE");
  if (location == "cells") key = "TYPE";
  const std::string branch = "tissue{builder=" + manifest["tissue"]["builder"].get<std::string>() + "}";
  if (location == "tissue" && key != "builder") location = branch;
  else if (location.rfind("tissue.", 0) == 0) location = branch + location.substr(6);  // a builder's nested object
  return {location, key};
}

bool under_free_location(const std::string& location, const std::set<std::string>& free_locations) {
  for (const auto& free : free_locations)
    if (location == free || location.rfind(free + ".", 0) == 0) return true;
  return false;
}

// The keys parse_scene reads for `manifest`, added to `read`.
void record_manifest_keys(const json& manifest, const std::set<std::string>& free_locations, KeySet& read) {
  KeyReadLog log;
  parse_scene(manifest);
  for (const auto& [path, key] : log.keys()) {
    const auto [location, schema_key] = schema_location(path, key, manifest);
    if (!under_free_location(location, free_locations)) read.emplace(location, schema_key);
  }
}

std::string listed(const KeySet& keys) {
  std::string text;
  for (const auto& [location, key] : keys) text += "\n  " + (location.empty() ? "(top)" : location) + " : " + key;
  return text;
}

KeySet minus(const KeySet& a, const KeySet& b) {
  KeySet out;
  for (const auto& k : a)
    if (!b.count(k)) out.insert(k);
  return out;
}

SweepFile read_example_sweep(const fs::path& file) {
  return read_sweep(read_manifest_file(file.string()), [&](const std::string& manifest) {
    return read_manifest_file((file.parent_path() / manifest).string());
  });
}

// Manifests that together make the code read every key it knows: each
// builder (the fibrotic patch with both arrangements), both forms of
// output.traces, each form of a region stimulus target, every optional
// section (the tissue's settle among them).
std::vector<json> coverage_manifests() {
  const json full = json::parse(R"({
    "fibrodem": 1, "name": "every_key", "seed": 3, "duration_ms": 10,
    "effects": ["electrophysiology", "coupling", "contraction", "mechanics", "mechano_electric_feedback"],
    "tissue": {"builder": "single_cell", "type": "myocyte"},
    "cells": {
      "myocyte": {"model": "colman", "variant": "colman2013", "parameters": {"g_K1_scale": 1.0},
                  "initial_state": {"V": -80}, "calcium_feedback": false,
                  "myofilament": {"model": "rice", "variant": "human_atrial", "parameters": {}, "initial_state": {}},
                  "settle": {"ms": 10, "pacing": {"period_ms": 5, "duration_ms": 1, "amplitude_pA": 2000}}},
      "fibroblast": {"model": "passive_fibroblast", "myofilament": "rice"}
    },
    "coupling": {"law": "gap_junction", "D_m_nS": 1000, "D_f_nS": 2, "scheme": "implicit", "dt_ms": 0,
                 "regions": [{"shape": "rectangle", "x_mm": [0, 1], "y_mm": [0, 1], "scale": 0.5},
                             {"shape": "ellipse", "x_mm": [0, 1], "y_mm": [0, 1], "D_m_nS": 10, "D_m_side_nS": 5,
                              "D_f_nS": 1}],
                 "field": {"x_mm": [0, 1], "y_mm": [0, 1], "scale": [[1, 0.5]], "between": "nearest"}},
    "mechanics": {"solver": "dem", "contact_law": "linear_bond", "contact_law_parameters": {}},
    "mechano_electric_feedback": {"G_SAC_nS": 5, "E_SAC_mV": 0, "lambda_max": 1.1},
    "stimulus": [{"target": {"x_min_frac": 0, "x_max_frac": 1, "y_min_frac": 0, "y_max_frac": 0.5, "type": "myocyte"},
                  "start_ms": 1, "duration_ms": 2, "amplitude_pA": 2000, "period_ms": 5, "count": 2}],
    "solver": {"method": "auto", "accuracy": 0.5, "max_step_ms": 0, "linear_solver": "auto", "threads": "auto",
               "lookup_tables": true, "simd": true},
    "output": {"dir": "", "progress_every_s": 1, "tissue_picture": false, "maps": false, "vtk_format": "xml",
               "report": false,
               "traces": {"cells": [0], "variables": ["V"], "every_ms": 1, "from_ms": 0},
               "snapshots": {"every_ms": 5, "from_ms": 0, "png": true, "vtk": true},
               "checkpoint": {"every_ms": 5, "keep": 2},
               "biomarkers": {"from_ms": 0, "rmp": "pre_upstroke", "rmp_window_ms": 5, "rmp_gap_ms": 2, "cv": "fit"},
               "reentry": {"every_ms": 1, "from_ms": 0, "tau_ms": 10, "V_star_mV": -50, "link_mm": 1,
                           "f_min_hz": 1, "f_max_hz": 30, "clinical_f_min_hz": 3, "clinical_f_max_hz": 12,
                           "ps_density_bin_mm": 1}},
    "initial_state": {"from": "some_run", "time_ms": 5},
    "settle": {"ms": 5}
  })");
  std::vector<json> manifests;
  json m = full;
  m["plugin_path"] = FIBRODEM_BINARY_DIR "/plugins";
  manifests.push_back(m);
  m = full;
  m["plugin_path"] = json::array({FIBRODEM_BINARY_DIR "/plugins"});
  m["tissue"] = {{"builder", "cell_pair"}, {"fibroblasts", 2}};
  m["solver"] = {{"method", "cvode"}, {"rtol", 1e-6}, {"atol", 1e-8}, {"threads", 1}};
  m["output"]["traces"] = json::array({{{"cells", {0}}, {"variables", {"V"}}}, {{"cells", {1}}, {"every_ms", 1}, {"from_ms", 0}}});
  manifests.push_back(m);
  m = full;
  m["tissue"] = {{"builder", "strand"}, {"type", "myocyte"}, {"cells", 3}};
  m["solver"] = {{"method", "rush_larsen"}, {"dt_ms", 0.01}};
  // The other two forms of a region: a rectangle and a circle in mm.
  m["stimulus"][0]["target"] = {{"x_min_mm", -1}, {"x_max_mm", 1}, {"y_min_mm", -1}, {"y_max_mm", 1}, {"type", "myocyte"}};
  // The field's other form: a file.
  const auto field_file = testing::scratch_dir("schema_coupling_field") / "field.csv";
  std::ofstream(field_file) << "1\n";
  m["coupling"]["field"] = {{"x_mm", {0, 1}}, {"y_mm", {0, 1}}, {"file", field_file.string()}};
  manifests.push_back(m);
  m["coupling"]["field"] = full["coupling"]["field"];
  m["tissue"] = {{"builder", "in_series"}, {"width_mm", 0.1}, {"height_mm", 0.2}, {"fm_ratio", 0.41}};
  m["stimulus"][0]["target"] = {{"center_x_mm", 0}, {"center_y_mm", 0.1}, {"radius_mm", 0.05}, {"type", "myocyte"}};
  manifests.push_back(m);
  const json interstitial_keys = {{"max_rotation_deg", 10}, {"max_offset_um", 2}, {"fibroblast_radius_um", {1, 4}},
                                  {"growth_max", 1.5}, {"growth", "overlap"}, {"fill_attempts_per_um2", 0.07},
                                  {"max_fibroblast_particles", 0}, {"keep_unconnected_fibroblasts", false}};
  m["tissue"] = interstitial_keys;
  m["tissue"].update({{"builder", "interstitial"}, {"width_mm", 0.1}, {"height_mm", 0.2}, {"column_spacing_um", 24}});
  manifests.push_back(m);
  m["tissue"] = {{"builder", "fibrotic_patch"}, {"arrangement", "in_series"}, {"width_mm", 0.5}, {"height_mm", 0.5},
                 {"fm_ratio", 0.1}, {"patch_width_mm", 0.2}, {"patch_height_mm", 0.2}, {"patch_centre_x_frac", 0.5},
                 {"patch_centre_y_frac", 0.5}, {"patch_fibroblast_fraction", 1}};
  manifests.push_back(m);
  m["tissue"] = interstitial_keys;
  m["tissue"].update({{"builder", "fibrotic_patch"}, {"arrangement", "interstitial"}, {"column_stride", 2}});
  manifests.push_back(m);
  m["tissue"] = {{"builder", "fibrotic_sheet"}, {"width_mm", 0.2}, {"length_mm", 0.5},
                 {"fibrosis", {{"density", 0.1}, {"pattern", "diffuse"}, {"as", "fibroblasts"}}}};
  manifests.push_back(m);
  m["tissue"]["fibrosis"] = {{"density", 0.1}, {"pattern", "patchy"}, {"correlation_length_mm", 0.1}};
  manifests.push_back(m);
  m["tissue"]["fibrosis"] = {{"density", 0.1}, {"pattern", "interstitial"}, {"line_length_mm", 0.25}};
  manifests.push_back(m);
  m["tissue"]["fibrosis"] = {{"density", 0.1}, {"pattern", "compact"}, {"centre_x_frac", 0.5}, {"centre_y_frac", 0.5},
                             {"aspect", 2}};
  manifests.push_back(m);
  return manifests;
}

std::string schema_error(SchemaKind kind, const json& document) {
  try {
    check_against_schema(kind, document);
  } catch (const ManifestError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("every example manifest and sweep file validates against its schema and sets up") {
  int manifests = 0, sweeps = 0;
  for (const auto& file : testing::example_files()) {
    CAPTURE(file.string());
    const json document = read_manifest_file(file.string());
    if (document.contains("fibrodem_sweep")) {
      // Each point's manifest too (parsed, not set up: the points differ from
      // the base manifest, set up below, in values only).
      const SweepFile sweep = read_example_sweep(file);
      CHECK_NOTHROW(check_against_schema(SchemaKind::sweep, document));
      for (const auto& point : sweep.points) CHECK_NOTHROW(parse_scene(point_manifest(sweep, point)));
      ++sweeps;
    } else {
      CHECK_NOTHROW(check_against_schema(SchemaKind::manifest, document));
      // As `fibrodem validate` does: parse, build the tissue, load the plugins.
      Scene scene = parse_scene(document);
      scene.output.dir.clear();
      CHECK_NOTHROW(Simulation{scene});
      ++manifests;
    }
  }
  // Floors, to notice a walk that finds little or nothing: examples/ holds 17
  // manifests and 7 sweep files, examples/paper/ 6 sweep files,
  // examples/arrhythmia/ 2 manifests, and examples are only ever added.
  CHECK(manifests >= 19);
  CHECK(sweeps >= 13);
}

TEST_CASE("the manifest reader reads exactly the keys the manifest schema lists") {
  std::set<std::string> free_locations;
  const KeySet in_schema = schema_keys(SchemaKind::manifest, &free_locations);
  // The free-key objects of the schema: parameters, initial states, the contact law's parameters.
  CHECK(free_locations.count("cells.TYPE.parameters") == 1);
  CHECK(free_locations.count("mechanics.contact_law_parameters") == 1);
  KeySet read;
  for (const auto& manifest : coverage_manifests()) {
    CAPTURE(manifest["tissue"].dump());
    record_manifest_keys(manifest, free_locations, read);
  }
  for (const auto& file : testing::example_files()) {
    const json document = read_manifest_file(file.string());
    if (!document.contains("fibrodem_sweep")) record_manifest_keys(document, free_locations, read);
  }
  const KeySet read_not_listed = minus(read, in_schema);
  const KeySet listed_not_read = minus(in_schema, read);
  CHECK_MESSAGE(read_not_listed.empty(), "keys the code reads that the schema lacks:" << listed(read_not_listed));
  CHECK_MESSAGE(listed_not_read.empty(), "keys the schema lists that the code never reads:" << listed(listed_not_read));
  // A floor to notice a walk that finds little or nothing: format 1 of the
  // schema had 151 (location, key) pairs and keys are only ever added.
  CHECK(in_schema.size() >= 151);
}

TEST_CASE("the manifest reader's numbers have the schema's ranges and defaults, value by value") {
  std::set<std::string> free_locations;
  std::map<std::pair<std::string, std::string>, json> schema_of;  // (location, key) -> the key's schema
  for (const auto& section : schema_sections(schema_document(SchemaKind::manifest)))
    for (const auto& key : section.keys) schema_of[{section.location, key.name}] = key.schema;
  // Read only where the manifest gives them, the first traces block's value
  // then holding for all: their defaults are TraceSpec's, checked below.
  const std::set<std::string> read_where_given = {"output.traces.every_ms", "output.traces.from_ms",
                                                  "output.traces[].every_ms", "output.traces[].from_ms"};
  // Bounded by another value as well (the patch within the tissue): the
  // reader's bound may only be tighter than the schema's.
  const std::set<std::string> bounded_by_another = {"tissue{builder=fibrotic_patch}.patch_height_mm",
                                                    "tissue{builder=fibrotic_patch}.patch_width_mm"};
  std::string differences;
  std::size_t compared = 0;
  for (const auto& manifest : coverage_manifests()) {
    KeyReadLog log;
    parse_scene(manifest);
    for (const auto& [where, rule] : log.numbers()) {
      const auto at = schema_location(where.first, where.second, manifest);
      const auto it = schema_of.find(at);
      if (it == schema_of.end()) continue;  // a free key (a parameter): no schema of its own
      const json& schema = it->second;
      const std::string name = at.first + "." + at.second;
      ++compared;
      const auto bound = [&](const char* word, double reader) {
        if (!schema.contains(word)) return;
        const double listed = schema[word].get<double>();
        if (bounded_by_another.count(name) && (word == std::string("maximum") ? reader <= listed : reader >= listed))
          return;
        if (listed != reader)
          differences += "\n  " + name + ": " + word + " " + schema[word].dump() + " in the schema, " +
                         format_number(reader) + " in the reader";
      };
      bound("minimum", rule.min);
      bound("maximum", rule.max);
      if (schema.contains("default") && schema["default"].is_number() && !read_where_given.count(name) &&
          (!rule.fallback || schema["default"].get<double>() != *rule.fallback))
        differences += "\n  " + name + ": default " + schema["default"].dump() + " in the schema, " +
                       (rule.fallback ? format_number(*rule.fallback) : std::string("none")) + " in the reader";
    }
  }
  CHECK_MESSAGE(differences.empty(), "numbers whose reader and schema disagree:" << differences);
  CHECK(compared >= 50);
  // The traces' defaults where the manifest does not give them.
  json without = testing::passive_cell_manifest();
  without["output"]["traces"].erase("every_ms");
  const Scene plain = parse_scene(without);
  const json& traces = schema_of.at({"output.traces", "every_ms"});
  CHECK(plain.output.traces.every_ms == traces["default"].get<double>());
  CHECK(plain.output.traces.from_ms == schema_of.at({"output.traces", "from_ms"})["default"].get<double>());
}

TEST_CASE("the sweep reader reads exactly the keys the sweep schema lists") {
  std::set<std::string> free_locations;
  const KeySet in_schema = schema_keys(SchemaKind::sweep, &free_locations);
  CHECK(free_locations == std::set<std::string>{"grid", "set"});
  const json sweep = {{"fibrodem_sweep", 1}, {"manifest", "base.json"}, {"set", {{"solver.dt_ms", 0.01}}},
                      {"grid", {{"coupling.D_f_nS", {1, 2}}}}, {"seeds", 2}};
  KeyReadLog log;
  read_sweep(sweep, [](const std::string&) { return testing::passive_cell_manifest(); });
  KeySet read;
  for (const auto& [path, key] : log.keys())
    if (path.empty()) read.emplace(path, key);
  CHECK_MESSAGE(read == in_schema, "read:" << listed(read) << "\nschema:" << listed(in_schema));
}

TEST_CASE("the schema's closed lists are the code's registries") {
  const json& root = schema_document(SchemaKind::manifest);
  std::vector<std::string> methods = {"auto"};
  for (const auto& entry : integrators()) methods.push_back(entry.name);
  CHECK(root["definitions"]["solver"]["properties"]["method"]["enum"].get<std::vector<std::string>>() == methods);
  std::set<std::string> builders;
  for (const auto& [name, factory] : tissue_builders()) builders.insert(name);
  const auto listed_builders = root["definitions"]["tissue"]["properties"]["builder"]["enum"].get<std::set<std::string>>();
  CHECK(listed_builders == builders);
  CHECK(root["definitions"]["tissue"]["oneOf"].size() == builders.size());
  CHECK(root["properties"]["effects"]["items"]["enum"].get<std::vector<std::string>>() == known_effects());
}

TEST_CASE("schema errors name the JSON path and what the schema expects") {
  json m = testing::passive_cell_manifest();
  CHECK(schema_error(SchemaKind::manifest, m) == "(no error)");
  // Numbers and ranges as in schema/manifest-1.schema.json (tissue_in_series.width_mm: [0.025, 100]).
  m["tissue"] = {{"builder", "in_series"}, {"width_mm", 0}};
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: tissue.width_mm: expected a number in [0.025, 100], got 0 (manifest schema)");
  m = testing::passive_cell_manifest();
  m["tissue"]["cells"] = 3;  // single_cell takes only `type`
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: tissue.cells: unknown key (known here: builder, type) (manifest schema)");
  m = testing::passive_cell_manifest();
  m.erase("duration_ms");
  CHECK(schema_error(SchemaKind::manifest, m) == "manifest: duration_ms: required value is missing (manifest schema)");
  m = testing::passive_cell_manifest();
  m["stimulus"][0]["target"] = 7;
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: stimulus[0].target: expected one of \"myocyte\", \"fibroblast\" or a list of at least 1 "
        "(each: an integer >= 0) or an object, got 7 (manifest schema)");
  m = testing::passive_cell_manifest();
  m["solver"] = {{"method", "auto"}, {"dt_ms", 0.01}};
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: solver.dt_ms: not allowed here: method auto chooses dt_ms, rtol and atol itself (manifest schema)");
  m = testing::passive_cell_manifest();
  m["solver"]["threads"] = "many";
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: solver.threads: expected an integer in [0, 1024] or \"auto\", got \"many\" (manifest schema)");
  m = testing::passive_cell_manifest();
  m["cells"]["wizard"] = {{"model", "passive_fibroblast"}};
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: cells.wizard: expected a key that is one of \"myocyte\", \"fibroblast\" (manifest schema)");
  m = testing::passive_cell_manifest();
  m["cells"]["fibroblast"]["parameters"] = {{"C_pF", "big"}};
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: cells.fibroblast.parameters.C_pF: expected a number, got \"big\" (manifest schema)");

  const json sweep = {{"fibrodem_sweep", 1}, {"manifest", "m.json"}, {"grid", {{"coupling.D_f_nS", json::array()}}}};
  CHECK(schema_error(SchemaKind::sweep, sweep) ==
        "manifest: grid.coupling.D_f_nS: expected a list of at least 1, got [] (sweep schema)");
  json no_path = sweep;
  no_path["grid"] = {{"", {1}}};
  CHECK(schema_error(SchemaKind::sweep, no_path) == "manifest: grid.: expected a key that is a non-empty string (sweep schema)");
}

TEST_CASE("the reader's own messages come first, and the schema takes what the reader takes") {
  // Both refuse an unknown effect; the reader's message, which names it as an effect, is the one given.
  json m = testing::passive_cell_manifest();
  m["effects"] = {"telepathy"};
  CHECK_THROWS_WITH_AS(parse_scene(m), doctest::Contains("effects[0]: unknown effect \"telepathy\""), ManifestError);
  // An integer written 2.0 is an integer to the reader and to JSON Schema (draft 6 on), not 2.5.
  m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", 2.0}};
  CHECK(schema_error(SchemaKind::manifest, m) == "(no error)");
  CHECK_NOTHROW(parse_scene(m));
  m["tissue"]["cells"] = 2.5;
  CHECK(schema_error(SchemaKind::manifest, m) ==
        "manifest: tissue.cells: expected an integer in [1, 1000000], got 2.5 (manifest schema)");
}

TEST_CASE("the embedded schemas are the files in schema/, and docs/reference/ is what the generator writes") {
  CHECK(std::string(schema_text(SchemaKind::manifest)) == testing::read_file(kSource / "schema" / "manifest-1.schema.json"));
  CHECK(std::string(schema_text(SchemaKind::sweep)) == testing::read_file(kSource / "schema" / "sweep-1.schema.json"));
  for (const auto& reference : {std::pair{SchemaKind::manifest, "manifest.md"}, std::pair{SchemaKind::sweep, "sweep_file.md"}}) {
    const std::string file = reference.second;
    const std::string kind = schema_kind_name(reference.first);
    const bool current = schema_markdown(reference.first) == testing::read_file(kSource / "docs" / "reference" / file);
    CHECK_MESSAGE(current, "docs/reference/" << file << " is not what the schema gives now: regenerate it with "
                                            << "build/fibrodem schema --markdown " << kind << " > docs/reference/" << file);
  }
  CHECK(schema_document(SchemaKind::manifest)["$id"] == "https://fibrodem.invalid/schema/manifest-1.schema.json");
}
