#include "run/run_summary.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "measure/conduction_velocity.hpp"
#include "mechanics/contact_law.hpp"

namespace fibrodem {

json mean_biomarkers(const std::vector<BeatBiomarkers>& beats) {
  json means = json::object();
  for (CellType type : {CellType::myocyte, CellType::fibroblast}) {
    const char* fields[] = {"rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms"};
    double sum[4] = {0, 0, 0, 0};
    int count[4] = {0, 0, 0, 0};
    int measured = 0, not_fired = 0;
    for (const auto& b : beats) {
      if (b.type != type) continue;
      if (!fired(b)) {
        ++not_fired;
        continue;
      }
      ++measured;
      const double values[4] = {b.rmp_mV, b.apo_mV, b.apd90_ms, b.dvdt_max_mV_per_ms};
      for (int i = 0; i < 4; ++i)
        if (std::isfinite(values[i])) {
          sum[i] += values[i];
          ++count[i];
        }
    }
    if (measured + not_fired == 0) continue;
    json m;
    for (int i = 0; i < 4; ++i) m[fields[i]] = count[i] ? json(sum[i] / count[i]) : json(nullptr);
    m["beats_measured"] = measured;
    m["beats_not_fired"] = not_fired;
    means[cell_type_name(type)] = m;
  }
  return means;
}

json conduction(const Tissue& tissue, const Stimulus& stimulus, const std::vector<BeatBiomarkers>& beats,
               const std::string& method) {
  json per_beat = json::array();
  // (Not on a rank other than 0 of a split run, which freed the centres:
  // rank 0 measures the conduction of every rank's beats.)
  if (tissue.cell_count() < 2 || !tissue.centres_whole()) return per_beat;
  std::vector<bool> stimulated(tissue.cell_count(), false);
  for (const auto& train : stimulus.trains())
    for (int c : train.cells) stimulated[c] = true;
  std::map<int, std::vector<ConductionSample>> beats_by_index;
  for (const auto& b : beats)
    beats_by_index[b.beat].push_back(
        {tissue.y_um[b.cell], b.activation_ms, stimulated[b.cell], carried_wave(b)});
  for (const auto& [beat, beat_cells] : beats_by_index)
    if (const auto fit = method == "transit" ? transit_conduction_velocity(beat_cells) : fit_conduction_velocity(beat_cells))
      per_beat.push_back({{"beat", beat}, {"cv_cm_per_s", fit->cv_cm_per_s}, {"method", method},
                          {"r_squared", std::isfinite(fit->r_squared) ? json(fit->r_squared) : json(nullptr)},
                          {"cells_used", fit->cells_used}, {"window_um", {fit->from_um, fit->to_um}}});
  return per_beat;
}

namespace {
json model_used(const Population& pop) {
  json parameters = json::object();
  for (std::size_t k = 0; k < pop.params.size(); ++k) parameters[pop.info().parameters[k].name] = pop.params[k];
  return {{"model", pop.info().name}, {"variant", pop.variant}, {"parameters", parameters}};
}

// The DEM's contact law: its plugin's provenance and every parameter value used.
json contact_law_summary(const DemSpec& spec) {
  const auto law = load_contact_law(spec.contact_law);  // loaded already: a look-up
  const ContactLawRecord record = contact_law_record(spec.contact_law);
  const std::vector<double> values = contact_law_parameter_values(law->info(), spec);
  json parameters = json::object();
  for (std::size_t k = 0; k < values.size(); ++k) parameters[law->info().parameters[k].name] = values[k];
  return {{"name", record.name}, {"version", record.version}, {"file", record.file}, {"sha256", record.sha256},
          {"parameters", parameters}};
}
}  // namespace

json models_used(const CellSystem& system) {
  json models = json::object();
  for (const auto& pop : system.populations) models[cell_type_name(pop.type)] = model_used(pop);
  for (const auto& m : system.myofilaments)
    models[cell_type_name(system.populations[static_cast<std::size_t>(m.host)].type)]["myofilament"] = model_used(m.pop);
  return models;
}

json run_summary(const RunFacts& f) {
  json s;
  s["fibrodem_version"] = FIBRODEM_VERSION;
  s["name"] = f.scene.name;
  s["status"] = f.status;
  if (!f.error.empty()) s["error"] = f.error;
  s["manifest"] = f.scene.manifest;
  s["plugins"] = json::array();
  for (const auto& r : f.registry.loaded())
    s["plugins"].push_back({{"name", r.name}, {"version", r.version}, {"file", r.file.string()},
                            {"sha256", r.sha256}});
  s["models"] = models_used(f.system);
  s["effects"] = json::array();
  s["processes"] = json::array();
  for (const auto& p : f.plan.built) {
    s["effects"].push_back(p.name);
    s["processes"].push_back({{"name", p.name}, {"reason", p.reason}});
  }
  s["notes"] = f.plan.notes;
  s["warnings"] = f.warnings;
  s["integrator"] = f.integrator;
  if (!f.solver_choice.empty())
    s["solver_choice"] = {{"method", f.scene.solver.method}, {"rtol", f.scene.solver.rtol},
                          {"atol", f.scene.solver.atol}, {"why", f.solver_choice}};
  s["wall_time_s"] = f.wall_s;
  s["steps"] = f.steps;
  s["mpi_ranks"] = f.mpi_ranks;
  s["simulated_ms"] = f.simulated_ms;
  if (!f.last_checkpoint.is_null()) s["last_checkpoint"] = f.last_checkpoint;
  if (!f.resumed_from.is_null()) s["resumed_from"] = f.resumed_from;
  const auto myocytes = f.tissue.count(CellType::myocyte), fibroblasts = f.tissue.count(CellType::fibroblast);
  s["cells"] = {{"myocyte", myocytes}, {"fibroblast", fibroblasts}};
  s["fm_ratio"] = myocytes ? json(static_cast<double>(fibroblasts) / static_cast<double>(myocytes))
                           : json(nullptr);
  if (!f.trace_units.empty()) s["trace_units"] = f.trace_units;
  s["mean_biomarkers"] = mean_biomarkers(f.beats);
  s["conduction"] = conduction(f.tissue, f.system.stimulus, f.beats, f.scene.output.cv_method);
  s["cv_cm_per_s"] = s["conduction"].empty() ? json(nullptr) : s["conduction"].back()["cv_cm_per_s"];
  if (!f.reentry.is_null()) s["reentry"] = f.reentry;
  s["peak_strain"] = f.mechanics ? json{{"xx", f.peak_strain[0]}, {"yy", f.peak_strain[1]}, {"xy", f.peak_strain[2]}}
                                 : json(nullptr);
  if (f.mechanics) s["mechanics_step_ms"] = f.mechanics_step_ms;  // the smallest step taken
  if (f.mechanics) s["contact_law"] = contact_law_summary(f.scene.mechanics);
  // Where the run's wall time went (s); `other` is what no entry accounts for.
  // Set-up (tissue, plugins, tables) precedes the run and has its own key.
  const double ionic = f.system.seconds[CellSystem::kIonic], coupling = f.system.seconds[CellSystem::kCoupling],
               myofilament = f.system.seconds[CellSystem::kMyofilament];
  const double accounted = ionic + coupling + myofilament + f.mechanics_seconds + f.measurement_seconds +
                           f.output_seconds + f.integrator_seconds;
  s["wall_time_by_process_s"] = {{"ionic_models", ionic},
                                 {"coupling", coupling},
                                 {"myofilament_models", myofilament},
                                 {"mechanics", f.mechanics_seconds},
                                 {"measurement", f.measurement_seconds},
                                 {"output", f.output_seconds},
                                 {"integrator", f.integrator_seconds},
                                 {"other", std::max(0.0, f.wall_s - accounted)}};
  s["set_up_time_s"] = f.set_up_seconds;
  return s;
}

void write_summary(const std::filesystem::path& dir, const json& summary) {
  // (A name of this process's own: ranks of a split run that fail at once
  // may each write one; the last rename wins, whole.)
  const std::filesystem::path tmp = dir / ("summary.json." + std::to_string(getpid()) + ".tmp");
  {
    std::ofstream f(tmp, std::ios::trunc);
    f << summary.dump(2, ' ', false, json::error_handler_t::replace) << '\n';  // (the manifest's strings as given)
  }
  std::filesystem::rename(tmp, dir / "summary.json");  // atomic: never a half-written summary
}

}  // namespace fibrodem
