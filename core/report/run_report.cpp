#include "report/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <set>
#include <stdexcept>

#include "io/csv_writer.hpp"
#include "io/plot_svg.hpp"
#include "measure/beat_activations.hpp"
#include "report/singularity_panel.hpp"
#include "report/biomarker_spread.hpp"
#include "report/html_document.hpp"
#include "report/snapshot_frames.hpp"
#include "report/trace_panels.hpp"
#include "util/json_reader.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

// The last lines of run.log shown in the page (the whole log is beside it).
constexpr std::size_t kLogTailLines = 400;
// traces.csv and phase_singularities.csv above this size are not read into
// the page's plots (read as text rows they would take ~15x their size in
// memory); the report says so. biomarkers.csv is read row by row, at any size.
constexpr std::uintmax_t kMostCsvBytes = 128ull << 20;

struct RunFolder {
  fs::path dir;
  json summary;  // null if summary.json is missing or unreadable
  std::string summary_problem;
  std::optional<CsvTable> traces;
  std::optional<BiomarkerDigest> biomarkers;  // read row by row: any size
  std::vector<std::string> too_large;  // CSV files left out for their size
  std::vector<std::string> log_tail;
  std::vector<std::string> log_problems;  // [warning] and [error] lines of the whole log
};

// The folder's files; summary.json's content is `known_summary` when given.
RunFolder read_folder(const fs::path& dir, const json* known_summary) {
  RunFolder f{dir, nullptr, "", std::nullopt, std::nullopt, {}, {}, {}};
  std::error_code error;
  const auto bytes = fs::file_size(dir / "traces.csv", error);
  if (!error && bytes > kMostCsvBytes)
    f.too_large.push_back("traces.csv (" + std::to_string(bytes >> 20) + " MB) is too large to plot here");
  else
    f.traces = read_csv_table(dir / "traces.csv");
  std::set<int> traced_cells;  // whose type the traces' legend names
  if (f.traces)
    for (const auto& column : f.traces->header)
      if (const int cell = parse_trace_heading(column).cell; cell >= 0) traced_cells.insert(cell);
  f.biomarkers = digest_biomarkers_csv(dir / "biomarkers.csv", traced_cells);
  if (known_summary) {
    // As summary.json holds it (write_summary): a NaN is null there, text
    // not UTF-8 is replaced; the page then reads as one written later.
    f.summary = json::parse(known_summary->dump(-1, ' ', false, json::error_handler_t::replace));
  } else if (std::ifstream in(dir / "summary.json"); !in || !fs::is_regular_file(dir / "summary.json", error)) {
    f.summary_problem = "no summary.json: the run never started, or this is not a run's folder";
  } else {
    try {
      f.summary = json::parse(in);
    } catch (const json::exception& e) {
      f.summary_problem = std::string("summary.json cannot be read: ") + e.what();
    }
  }
  std::ifstream log;  // (a regular file only, as for the CSV files)
  if (fs::is_regular_file(dir / "run.log", error)) log.open(dir / "run.log");
  std::deque<std::string> tail;
  for (std::string line; std::getline(log, line);) {
    if (line.find("] [warning] ") != std::string::npos || line.find("] [error] ") != std::string::npos ||
        line.find("] [critical] ") != std::string::npos)
      f.log_problems.push_back(line);
    tail.push_back(std::move(line));
    if (tail.size() > kLogTailLines) tail.pop_front();
  }
  f.log_tail.assign(tail.begin(), tail.end());
  return f;
}

std::string text_of(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {  // 6 significant digits: 500, 0.0886707, 684.763
    return significant_digits(v.get<double>(), 6);
  }
  return v.dump(-1, ' ', false, json::error_handler_t::replace);
}

// s[key] if s has it, else null (which iterates as empty).
const json& member(const json& s, const char* key) {
  static const json kNull;
  return s.is_object() && s.contains(key) ? s[key] : kNull;
}

std::string field(const json& s, const char* key) { return s.is_object() && s.contains(key) ? text_of(s[key]) : ""; }

// Errors and warnings first, where nobody can miss them.
void status_section(HtmlDocument& page, const RunFolder& f) {
  if (f.summary.is_null()) {
    page.notice("error", f.summary_problem, {});
    if (!f.too_large.empty()) page.notice("warning", "left out", f.too_large);
    return;
  }
  const std::string status = field(f.summary, "status");
  const std::string simulated = field(f.summary, "simulated_ms");
  if (status == "completed") {
    page.notice("ok", "completed: " + simulated + " ms simulated", {});
  } else if (status == "failed") {
    page.notice("error", "failed at t = " + simulated + " ms", {field(f.summary, "error")});
  } else if (status == "interrupted") {
    page.notice("warning", "interrupted at t = " + simulated + " ms", {field(f.summary, "error")});
  } else {
    page.notice("error", "status \"" + status + "\": the run was killed or is still running (" + simulated +
                             " ms simulated when summary.json was last written)", {});
  }
  std::vector<std::string> warnings;
  if (f.summary.contains("warnings"))
    for (const auto& w : f.summary["warnings"]) warnings.push_back(text_of(w));
  for (const auto& line : f.log_problems)
    if (std::find(warnings.begin(), warnings.end(), line) == warnings.end()) warnings.push_back(line);
  warnings.insert(warnings.end(), f.too_large.begin(), f.too_large.end());
  if (!warnings.empty()) page.notice("warning", std::to_string(warnings.size()) + " warning(s)", warnings);
}

void scene_section(HtmlDocument& page, const json& s) {
  page.heading(2, "Scene", "scene");
  const json m = s.value("manifest", json::object());
  std::vector<std::pair<std::string, std::string>> items = {
      {"name", field(s, "name")},
      {"fibrodem", field(s, "fibrodem_version")},
      {"seed", field(m, "seed")},
      {"duration", field(m, "duration_ms") + " ms (simulated: " + field(s, "simulated_ms") + " ms)"},
      {"tissue", text_of(m.value("tissue", json()))},
      {"cells", text_of(s.value("cells", json()))},
      {"F-M ratio", field(s, "fm_ratio")},
      {"integrator", field(s, "integrator")},
      {"steps", field(s, "steps")},
      {"wall time", field(s, "wall_time_s") + " s (set-up " + field(s, "set_up_time_s") + " s)"}};
  if (s.contains("solver_choice")) items.push_back({"solver choice", text_of(s["solver_choice"])});
  if (s.contains("peak_strain") && !s["peak_strain"].is_null()) items.push_back({"peak strain", text_of(s["peak_strain"])});
  if (s.contains("resumed_from")) items.push_back({"resumed from", text_of(s["resumed_from"])});
  page.definition_list(items);

  page.heading(3, "Models");
  std::vector<std::vector<std::string>> models;
  const json cells = m.value("cells", json::object());  // a named copy: items() of a temporary dangles
  for (const auto& [type, spec] : cells.items())
    models.push_back({type, field(spec, "model"), field(spec, "variant"),
                      spec.contains("parameters") ? text_of(spec["parameters"]) : "(the variant's)",
                      spec.contains("myofilament") ? text_of(spec["myofilament"]) : ""});
  page.table({"cell type", "model", "variant", "parameters set", "myofilament"}, models);
  std::vector<std::vector<std::string>> plugins;
  for (const auto& p : member(s, "plugins"))
    plugins.push_back({field(p, "name"), field(p, "version"), field(p, "sha256").substr(0, 16), field(p, "file")});
  page.table({"plugin", "version", "SHA-256 (first 16)", "file"}, plugins);
  // Every parameter value used (summary.json `models`, `contact_law`), folded away.
  auto parameters_used = [&](const std::string& title, const json& model) {
    std::string lines;
    for (const auto& [name, value] : member(model, "parameters").items()) lines += name + " = " + text_of(value) + "\n";
    if (!lines.empty()) page.details("parameters used: " + title, lines);
  };
  for (const auto& [type, model] : member(s, "models").items()) {
    parameters_used(type + " (" + field(model, "model") + ", variant " + field(model, "variant") + ")", model);
    if (model.contains("myofilament"))
      parameters_used(type + " myofilament (" + field(model["myofilament"], "model") + ")", model["myofilament"]);
  }
  if (s.contains("contact_law")) parameters_used("contact law " + field(s["contact_law"], "name"), s["contact_law"]);

  page.heading(3, "Effects built, and why");
  std::vector<std::vector<std::string>> processes;
  for (const auto& p : member(s, "processes")) processes.push_back({field(p, "name"), field(p, "reason")});
  page.table({"process", "reason"}, processes);
  std::vector<std::string> notes;
  for (const auto& n : member(s, "notes")) notes.push_back(text_of(n));
  if (!notes.empty()) page.notice("info", "notes", notes);

  page.heading(3, "Wall time by process");
  const double wall = member(s, "wall_time_s").is_number() ? member(s, "wall_time_s").get<double>() : 0.0;
  std::vector<std::vector<std::string>> times;
  for (const auto& [process, seconds] : member(s, "wall_time_by_process_s").items())
    if (seconds.is_number())
      times.push_back({process, fixed_decimals(seconds.get<double>(), 3),
                       wall > 0 ? fixed_decimals(100 * seconds.get<double>() / wall, 1) : ""});
  page.table({"process", "s", "% of wall"}, times);
  page.details("manifest as resolved", m.dump(2));
}

std::string plot_of(const std::vector<PlotPanel>& panels, std::size_t columns, int panel_height_px, const std::string& id) {
  const std::size_t rows = (panels.size() + columns - 1) / columns;
  return plot_svg(panels, {.width_px = 1200, .height_px = panel_height_px * static_cast<int>(rows), .font_px = 14,
                           .title = "", .columns = columns},
                  id);
}

void biomarker_section(HtmlDocument& page, const RunFolder& f) {
  page.heading(2, "Biomarkers per cell type", "biomarkers");
  if (!f.biomarkers || f.biomarkers->rows() == 0) {
    page.paragraph("No beats in biomarkers.csv (none recorded, or the file is missing).");
    return;
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& b : f.biomarkers->spread())
    rows.push_back({b.type, b.metric, std::to_string(b.n), fixed_decimals(b.mean, 2), fixed_decimals(b.sd, 2),
                    fixed_decimals(b.min, 2), fixed_decimals(b.max, 2)});
  std::string not_fired;
  for (const auto& [type, n] : f.biomarkers->not_fired())
    if (n > 0) not_fired += " " + std::to_string(n) + " " + type + " cell-beats did not fire: left out.";
  page.paragraph("Over every cell-beat in biomarkers.csv where the cell fired (summary.json's mean_biomarkers)." +
                 not_fired);
  page.table({"cell type", "biomarker", "cell-beats", "mean", "SD", "min", "max"}, rows);
  const auto panels = f.biomarkers->histograms();
  if (!panels.empty()) page.svg_figure("Biomarker histograms", plot_of(panels, std::min<std::size_t>(4, panels.size()), 300, "hist-"));
}

void conduction_section(HtmlDocument& page, const json& s) {
  if (!s.contains("conduction") || s["conduction"].empty()) return;
  page.heading(2, "Conduction", "conduction");
  std::vector<std::string> header;
  for (const auto& [key, v] : s["conduction"].front().items()) header.push_back(key);
  std::vector<std::vector<std::string>> rows;
  for (const auto& beat : s["conduction"]) {
    rows.emplace_back();
    for (const auto& key : header) rows.back().push_back(field(beat, key.c_str()));
  }
  page.table(header, rows);
}

void traces_section(HtmlDocument& page, const RunFolder& f) {
  page.heading(2, "Traces", "traces");
  if (!f.traces || f.traces->rows.empty()) {
    page.paragraph("No samples in traces.csv (nothing traced, or the file is missing).");
    return;
  }
  const auto types = f.biomarkers ? f.biomarkers->types() : std::map<int, std::string>{};
  std::map<std::string, std::string> units;
  if (f.summary.is_object() && f.summary.contains("trace_units") && f.summary["trace_units"].is_object())
    for (const auto& [variable, unit] : f.summary["trace_units"].items())
      if (unit.is_string()) units[variable] = unit.get<std::string>();
  const auto panels = trace_panels(*f.traces, types, units);
  for (std::size_t k = 0; k < panels.size(); ++k)
    page.svg_figure(panels[k].title, plot_of({panels[k]}, 1, 340, "trace" + std::to_string(k) + "-"));
}

// The beats of output.reentry (reentry.beats): their table, the
// dominant-frequency map, and the activation map of each beat drawn
// (activation_beat_<k>.png) under a slider.
void beats_section(HtmlDocument& page, const fs::path& dir, const json& reentry) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::pair<std::string, fs::path>> maps;
  for (const auto& b : member(reentry, "beats")) {
    rows.push_back({field(b, "beat"), field(b, "onset_ms"), field(b, "wave"), field(b, "first_activation_ms"),
                    field(b, "last_activation_ms"), field(b, "reached") + " / " + field(b, "counted"),
                    field(b, "unreached_fraction")});
    const fs::path map = dir / beat_map_name(b.value("beat", 0));
    if (fs::exists(map))
      maps.emplace_back("beat " + field(b, "beat") + ", " + field(b, "unreached_fraction") + " not reached", map);
  }
  if (!rows.empty()) {
    page.heading(3, "Beats");
    page.table({"beat", "stimulus onset (ms)", "wave", "first activation (ms)", "last activation (ms)",
                "myocytes reached", "unreached fraction"},
               rows);
  }
  page.begin_row();
  page.png_figure("Dominant frequency per cell (Hz)", dir / "dominant_frequency_map.png");
  if (fs::exists(dir / "clinical_dominant_frequency_map.png"))
    page.png_figure("Dominant frequency per cell, clinical band (Hz)", dir / "clinical_dominant_frequency_map.png");
  // Narrower than the snapshots: full-colour maps, up to kMostBeatMaps of them.
  if (!maps.empty()) page.png_animation("Activation map per beat", animation_frames(maps, kMostAnimationFrames, 480));
  page.end_row();
}

// The spiral and driver measures of output.reentry: the longest-lived
// track's measures and the highest-DF site, the tip paths over the last map
// and the PS density map.
void drivers_section(HtmlDocument& page, const fs::path& dir, const json& reentry) {
  std::vector<std::vector<std::string>> rows;
  for (const char* key : {"longest_track", "highest_dominant_frequency"})
    for (const auto& [name, value] : member(reentry, key).items()) rows.push_back({key, name, text_of(value)});
  if (!rows.empty()) {
    page.heading(3, "Spiral and driver measures");
    page.table({"of", "measure", "value"}, rows);
  }
  const bool paths = fs::exists(dir / "phase_singularity_paths.png");
  const bool density = fs::exists(dir / "phase_singularity_density_map.png");
  if (!paths && !density) return;
  page.begin_row();
  if (paths) page.png_figure("Tip paths over the last sample", dir / "phase_singularity_paths.png");
  if (density) page.png_figure("Phase singularity density (PS-s per cm2)", dir / "phase_singularity_density_map.png");
  page.end_row();
}

// With output.reentry: summary.json's reentry, its spiral and driver
// measures, its beats and maps, and the phase singularities' trajectories.
void reentry_section(HtmlDocument& page, const fs::path& dir, const json& s) {
  if (!s.is_object() || !s.contains("reentry") || !s["reentry"].is_object()) return;
  page.heading(2, "Re-entry", "reentry");
  std::vector<std::vector<std::string>> rows;
  for (const auto& [key, value] : s["reentry"].items())
    if (!value.is_array() && !value.is_object()) rows.push_back({key, text_of(value)});
  page.table({"measure", "value"}, rows);
  drivers_section(page, dir, s["reentry"]);
  beats_section(page, dir, s["reentry"]);
  std::error_code error;
  const auto bytes = fs::file_size(dir / "phase_singularities.csv", error);
  if (!error && bytes > kMostCsvBytes) {
    page.paragraph("phase_singularities.csv (" + std::to_string(bytes >> 20) + " MB) is too large to plot here.");
    return;
  }
  const auto table = read_csv_table(dir / "phase_singularities.csv");
  if (const auto panel = table ? singularity_trajectories(*table) : std::nullopt)
    page.svg_figure(panel->title, plot_of({*panel}, 1, 600, "ps-"));
  else
    page.paragraph("No phase singularity in phase_singularities.csv.");
}

void pictures_section(HtmlDocument& page, const fs::path& dir) {
  std::vector<std::pair<std::string, fs::path>> snapshots;
  if (fs::is_directory(dir))
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("snapshot_", 0) == 0 && entry.path().extension() == ".png")
        snapshots.emplace_back(name.substr(9, name.size() - 9 - 4), entry.path());
    }
  std::sort(snapshots.begin(), snapshots.end());
  for (auto& [label, file] : snapshots) {
    label.erase(0, label.find_first_not_of('0'));  // "000100.000_ms" -> "100.000_ms"
    if (label.empty() || label.front() == '.') label.insert(0, "0");
    label.replace(label.rfind('_'), 1, " ");
    label.insert(0, "t = ");
  }
  const bool tissue = fs::exists(dir / "tissue.png"), activation = fs::exists(dir / "activation_map.png");
  if (!tissue && !activation && snapshots.empty()) return;
  page.heading(2, "Tissue", "tissue");
  page.begin_row();
  if (tissue) page.png_figure("Tissue by cell type", dir / "tissue.png");
  if (activation) page.png_figure("Activation map (last beat)", dir / "activation_map.png");
  page.end_row();
  // At most kMostAnimationFrames of them, scaled down: the page stays small at any tissue size.
  if (!snapshots.empty()) {
    const auto frames = animation_frames(snapshots);
    page.png_animation("Membrane potential" + (frames.size() < snapshots.size()
                                                   ? " (" + std::to_string(frames.size()) + " of " +
                                                         std::to_string(snapshots.size()) + " snapshots)"
                                                   : std::string()),
                       frames);
  }
}

}  // namespace

namespace {

fs::path write_report_page(const fs::path& dir, const json* known_summary) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + " is not a folder");
  const RunFolder f = read_folder(dir, known_summary);
  const std::string name = f.summary.is_object() ? field(f.summary, "name") : dir.filename().string();
  HtmlDocument page("fibrodem run: " + name);
  // Plots first, tables after (what a reader looks at first), problems above all.
  status_section(page, f);
  traces_section(page, f);
  biomarker_section(page, f);
  if (f.summary.is_object()) conduction_section(page, f.summary);
  reentry_section(page, dir, f.summary);
  pictures_section(page, dir);
  if (f.summary.is_object()) scene_section(page, f.summary);
  std::string log;
  for (const auto& line : f.log_tail) log += line + "\n";
  page.heading(2, "run.log", "log");
  page.details(f.log_tail.size() < kLogTailLines ? "run.log" : "run.log (last " + std::to_string(kLogTailLines) + " lines)",
               log.empty() ? "(no run.log)" : log);
  const fs::path file = dir / "report.html";
  page.write(file);
  return file;
}

}  // namespace

fs::path write_run_report(const fs::path& dir) { return write_report_page(dir, nullptr); }

fs::path write_run_report(const fs::path& dir, const json& summary) { return write_report_page(dir, &summary); }

}  // namespace fibrodem
