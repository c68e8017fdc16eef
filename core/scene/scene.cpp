// The manifest's top level, its outputs, and --set overrides; each module's
// own section is read beside the module (coupling/coupling_spec.hpp, ...).
#include "scene/scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <tuple>

#include "scene/schema/schema_check.hpp"

namespace fibrodem {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// output.traces: {cells, variables, every_ms, from_ms}, or a list of such
// blocks; every_ms and from_ms, where blocks give them, must agree (one
// traces.csv, one time axis).
static TraceSpec read_traces(const json& raw, const std::string& path) {
  TraceSpec spec;
  const bool listed = raw.is_array();
  if (listed && raw.empty()) throw ManifestError(path, "expected at least one block {cells, variables}, got []");
  spec.blocks.clear();
  std::optional<std::pair<double, std::string>> every, from;
  for (std::size_t i = 0; i < (listed ? raw.size() : 1); ++i) {
    const std::string block_path = listed ? index_path(path, i) : path;
    JsonReader t(listed ? raw[i] : raw, block_path);
    TraceBlock block;
    block.path = block_path;
    const json& cells = t.raw("cells");
    if (!cells.is_null()) {
      if (!cells.is_array())
        throw ManifestError(t.path_of("cells"), "expected a list of cell indices, got " + describe_json(cells));
      block.cells = read_cell_indices(cells, t.path_of("cells"));
    }
    block.variables = t.text_list("variables", block.variables);
    // Each of every_ms and from_ms: the first block that gives it sets it.
    for (auto [key, value, first] : {std::tuple{"every_ms", &spec.every_ms, &every}, std::tuple{"from_ms", &spec.from_ms, &from}}) {
      if (!t.has(key)) continue;
      const double given = t.number(key, std::nullopt, std::string(key) == "every_ms" ? 1e-6 : 0.0, kInf);
      if (*first && given != (*first)->first)
        throw ManifestError(t.path_of(key), "expected " + describe_json((*first)->first) + " as " + (*first)->second +
                                                " gives (one traces.csv has one time axis), got " + describe_json(given));
      if (!*first) *first = std::pair{given, t.path_of(key)};
      *value = given;
    }
    t.finish();
    spec.blocks.push_back(std::move(block));
  }
  return spec;
}

// output.reentry: the delay must be a whole number of samples (the phase
// pairs each sample with an earlier one).
ReentrySpec read_reentry(JsonReader r) {
  ReentrySpec e;
  e.on = true;
  e.every_ms = r.number("every_ms", e.every_ms, 1e-3, 1e4);
  e.from_ms = r.number("from_ms", e.from_ms, 0.0, kInf);
  e.tau_ms = r.number("tau_ms", e.tau_ms, 1e-3, 1e4);
  const double samples = e.tau_ms / e.every_ms;
  if (samples < 1 - 1e-9 || std::abs(samples - std::round(samples)) > 1e-6 * samples)
    throw ManifestError(r.path_of("tau_ms"), "expected a whole multiple of every_ms (" + describe_json(e.every_ms) +
                                                 " ms), got " + describe_json(e.tau_ms));
  e.V_star_mV = r.number("V_star_mV", e.V_star_mV, -200.0, 200.0);
  e.link_mm = r.number("link_mm", e.link_mm, 1e-6, 1e6);
  e.f_min_hz = r.number("f_min_hz", e.f_min_hz, 0.0, 1e4);
  e.f_max_hz = r.number("f_max_hz", e.f_max_hz, 1e-3, 1e4);
  if (e.f_max_hz <= e.f_min_hz)
    throw ManifestError(r.path_of("f_max_hz"), "expected more than f_min_hz (" + describe_json(e.f_min_hz) +
                                                   " Hz), got " + describe_json(e.f_max_hz));
  e.clinical_f_min_hz = r.number("clinical_f_min_hz", e.clinical_f_min_hz, 0.0, 1e4);
  e.clinical_f_max_hz = r.number("clinical_f_max_hz", e.clinical_f_max_hz, 1e-3, 1e4);
  if (e.clinical_f_max_hz <= e.clinical_f_min_hz)
    throw ManifestError(r.path_of("clinical_f_max_hz"), "expected more than clinical_f_min_hz (" +
                                                            describe_json(e.clinical_f_min_hz) + " Hz), got " +
                                                            describe_json(e.clinical_f_max_hz));
  e.ps_density_bin_mm = r.number("ps_density_bin_mm", e.ps_density_bin_mm, 1e-3, 1e3);
  r.finish();
  return e;
}

OutputSpec read_output(JsonReader r) {
  OutputSpec o;
  o.dir = r.text("dir", std::string());
  o.progress_every_s = r.number("progress_every_s", 1.0, 0.0, kInf);
  if (r.has("traces")) o.traces = read_traces(r.raw("traces"), r.path_of("traces"));
  o.tissue_picture = r.boolean("tissue_picture", false);
  o.maps = r.boolean("maps", false);
  o.vtk_format = r.text("vtk_format", o.vtk_format, {"legacy", "xml"});
  o.report = r.boolean("report", true);
  if (r.has("snapshots")) {
    JsonReader sn = r.object("snapshots");
    o.snapshots.every_ms = sn.number("every_ms", std::nullopt, 1e-6, kInf);
    o.snapshots.from_ms = sn.number("from_ms", 0.0, 0.0, kInf);
    o.snapshots.png = sn.boolean("png", true);
    o.snapshots.vtk = sn.boolean("vtk", true);
    o.snapshots.strain = sn.boolean("strain", false);
    sn.finish();
  }
  if (r.has("checkpoint")) {
    JsonReader c = r.object("checkpoint");
    o.checkpoint.every_ms = c.number("every_ms", std::nullopt, 1e-3, kInf);
    o.checkpoint.keep = static_cast<int>(c.integer("keep", o.checkpoint.keep, 1, 1000000));
    c.finish();
  }
  if (r.has("biomarkers")) {
    JsonReader b = r.object("biomarkers");
    o.biomarkers_from_ms = b.number("from_ms", 0.0, 0.0, kInf);
    o.rmp_method = b.text("rmp", o.rmp_method, {"onset", "pre_upstroke"});
    if (o.rmp_method == "pre_upstroke") {
      o.rmp_window_ms = b.number("rmp_window_ms", o.rmp_window_ms, 0.01, 1000.0);
      o.rmp_gap_ms = b.number("rmp_gap_ms", o.rmp_gap_ms, 0.0, 1000.0);
    } else {
      for (const char* key : {"rmp_window_ms", "rmp_gap_ms"})
        if (b.has(key))
          throw ManifestError(b.path_of(key), "applies only with \"rmp\": \"pre_upstroke\" (rmp is \"onset\")");
    }
    o.cv_method = b.text("cv", o.cv_method, {"fit", "transit"});
    b.finish();
  }
  if (r.has("reentry")) o.reentry = read_reentry(r.object("reentry"));
  r.finish();
  return o;
}

}  // namespace

// plugin_path: a directory or a list of them, each an existing directory
// (relative to the working directory, as every path of a manifest).
static std::vector<std::string> read_plugin_path(JsonReader& top) {
  if (!top.has("plugin_path")) return {};
  const json& raw = top.raw("plugin_path");
  std::vector<std::string> dirs;
  if (raw.is_string()) dirs = {raw.get<std::string>()};
  else dirs = top.text_list("plugin_path", {});
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const std::string where = raw.is_string() ? std::string("plugin_path") : index_path("plugin_path", i);
    std::error_code ec;
    if (dirs[i].empty() || !std::filesystem::is_directory(dirs[i], ec))
      throw ManifestError(where, "expected an existing directory of plugins (libfibrodem_NAME.so), got \"" +
                                     dirs[i] + "\"" + (dirs[i].empty() ? "" : " (no such directory)"));
  }
  return dirs;
}

Scene parse_scene(const json& manifest) {
  JsonReader top(manifest, "");
  Scene scene;
  scene.manifest = manifest;
  top.integer("fibrodem", std::nullopt, kManifestFormat, kManifestFormat);
  scene.name = top.text("name", std::string("scene"));
  if (!std::regex_match(scene.name, std::regex("[A-Za-z0-9_.+-]+")))
    throw ManifestError("name", "expected letters, digits and _ . + - only, got " +
                                    describe_json(manifest.at("name")));
  scene.seed = static_cast<std::uint64_t>(top.integer("seed", 0, 0, std::numeric_limits<long long>::max()));
  scene.duration_ms = top.number("duration_ms", std::nullopt, 1e-9, 1e9);

  scene.effects_listed = top.has("effects");
  scene.effects = top.text_list("effects", {});
  for (std::size_t i = 0; i < scene.effects.size(); ++i)
    if (std::find(known_effects().begin(), known_effects().end(), scene.effects[i]) ==
        known_effects().end()) {
      std::string list;
      for (const auto& e : known_effects()) list += (list.empty() ? "" : ", ") + e;
      throw ManifestError(index_path("effects", i),
                          "unknown effect \"" + scene.effects[i] + "\" (expected one of " + list + ")");
    }

  JsonReader tissue = top.object("tissue");
  scene.tissue = make_tissue_builder(tissue);

  JsonReader cells = top.object("cells");
  for (const auto& [type_name, spec] : manifest.at("cells").items()) {
    CellType type;
    if (type_name == "myocyte") type = CellType::myocyte;
    else if (type_name == "fibroblast") type = CellType::fibroblast;
    else
      throw ManifestError(cells.path_of(type_name),
                          "unknown cell type (expected \"myocyte\" or \"fibroblast\")");
    scene.cells[type] = read_cell_type_spec(cells.object(type_name));
  }

  if (top.has("coupling")) scene.coupling = read_coupling_spec(top.object("coupling"));
  if (top.has("mechanics")) {
    JsonReader mechanics = top.object("mechanics");
    scene.mechanics = read_dem_spec(mechanics);
    mechanics.finish();
  }
  if (top.has("mechano_electric_feedback"))
    scene.mechano_electric = read_mechano_electric_spec(top.object("mechano_electric_feedback"));

  const json& stimuli = top.raw("stimulus");
  if (!stimuli.is_null()) {
    if (!stimuli.is_array())
      throw ManifestError("stimulus", "expected a list of stimulus objects, got " + describe_json(stimuli));
    for (std::size_t i = 0; i < stimuli.size(); ++i)
      scene.stimuli.push_back(read_stimulus_spec(JsonReader(stimuli[i], index_path("stimulus", i))));
  }

  if (top.has("solver")) scene.solver = read_solver_spec(top.object("solver"));
  if (top.has("output")) scene.output = read_output(top.object("output"));
  if (top.has("initial_state")) {
    JsonReader init = top.object("initial_state");
    scene.initial_state.from = init.text("from", std::nullopt);
    if (scene.initial_state.from.empty())
      throw ManifestError(init.path_of("from"), "expected a checkpoint file or a run's folder, got \"\"");
    scene.initial_state.time_ms = init.number("time_ms", -1.0, 0.0, 1e9);
    init.finish();
  }
  if (top.has("settle")) {
    JsonReader settle = top.object("settle");
    scene.settle.ms = settle.number("ms", std::nullopt, 0.0, 1e6);
    settle.finish();
  }
  scene.plugin_path = read_plugin_path(top);
  top.finish();
  // After the reader's own checks (their messages are the more specific): a
  // manifest the reader takes must also satisfy the published schema.
  check_against_schema(SchemaKind::manifest, manifest);
  return scene;
}

json read_manifest_file(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw ManifestError("", "cannot open manifest file '" + file + "'");
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    throw ManifestError("", "'" + file + "' is not valid JSON: " + e.what());
  }
}

void apply_override(json& manifest, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ManifestError("", "--set expects PATH=VALUE, got '" + assignment + "'");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;

  json* node = &manifest;
  std::string walked;
  static const std::regex part(R"(([^.\[\]]+)|\[(\d+)\])");
  for (auto it = std::sregex_iterator(path.begin(), path.end(), part); it != std::sregex_iterator(); ++it) {
    const auto& m = *it;
    if (m[1].matched) {
      walked = join_path(walked, m[1].str());
      if (!node->is_null() && !node->is_object())
        throw ManifestError(walked, "--set " + path + ": this value is not an object");
      node = &(*node)[m[1].str()];
    } else {
      const std::string digits = m[2].str();
      walked += "[" + digits + "]";
      // (More digits than any list has entries: no entry, and beyond what stoul takes.)
      if (!node->is_array() || digits.size() > 9 || std::stoul(digits) >= node->size())
        throw ManifestError(walked, "--set " + path + ": no such list entry");
      node = &(*node)[std::stoul(digits)];
    }
  }
  if (walked.empty()) throw ManifestError("", "--set expects PATH=VALUE, got '" + assignment + "'");
  *node = value;
}

}  // namespace fibrodem
