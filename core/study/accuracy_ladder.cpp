#include "study/accuracy_ladder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "model/plugin_registry.hpp"
#include "run/simulation.hpp"
#include "util/manifest_error.hpp"

namespace fibrodem {
namespace {

const std::vector<std::string> kAllMethods = {"euler", "rush_larsen", "rush_larsen2", "cvode", "adaptive", "auto"};
const std::vector<double> kDefaultDt_ms = {0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.25};
const std::vector<double> kDefaultRtol = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
const std::vector<double> kDefaultTol = {1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 1e-4};
const std::vector<double> kDefaultAccuracy_ms = {1, 0.5, 0.1, 0.01};

// Only V is compared: trace it alone (on the manifest's cells), write nothing.
json traced_v_alone(json base, double every_ms) {
  if (!base.contains("output") || !base["output"].is_object()) base["output"] = json::object();
  base["output"].erase("dir");
  json& traces = base["output"]["traces"];
  if (traces.is_array() && !traces.empty()) traces = json(traces[0]);  // a list of blocks: V of the first block's cells
  if (!traces.is_object()) traces = json::object();
  traces["variables"] = json::array({"V"});
  if (every_ms > 0) traces["every_ms"] = every_ms;
  return base;
}

void check_methods(const std::vector<std::string>& methods) {
  for (const auto& m : methods)
    if (std::find(kAllMethods.begin(), kAllMethods.end(), m) == kAllMethods.end())
      throw ManifestError("--methods", "unknown method '" + m +
                                           "' (expected euler, rush_larsen, rush_larsen2, cvode, adaptive or auto)");
}

void check_ladders_positive(const AccuracyLadder& l) {
  for (const auto& [values, option] : {std::pair{&l.dt_ms, "--dt"}, std::pair{&l.rtol, "--rtol"},
                                       std::pair{&l.tol, "--tol"}, std::pair{&l.accuracy_ms, "--accuracy"}})
    for (double v : *values)
      if (!(v > 0)) throw ManifestError(option, "expected positive values, got " + accuracy_number(v));
}

json solver_of(const json& base, const std::string& method, double setting, double atol_ratio) {
  json s = base.contains("solver") && base["solver"].is_object() ? base["solver"] : json::object();
  s["method"] = method;
  s["threads"] = 1;
  for (const char* key : {"dt_ms", "rtol", "atol", "accuracy"}) s.erase(key);  // each method its own
  if (method == "cvode") {
    s["rtol"] = setting;
    s["atol"] = setting * atol_ratio;
  } else if (method == "adaptive") {
    s["rtol"] = setting;
    s["atol"] = setting;
  } else if (method == "auto") {
    s["accuracy"] = setting;
  } else {
    s["dt_ms"] = setting;
  }
  return s;
}

// The reference (and its check) evaluate the exact model: a ladder run with
// solver.lookup_tables then shows the tables' error with the integrator's.
json exact_cvode(const AccuracyLadder& l, double rtol) {
  json s = solver_of(l.base, "cvode", rtol, l.atol_ratio);
  s.erase("lookup_tables");
  return s;
}

// Whether t is a whole multiple of dt (samples then fall on step ends).
bool multiple_of(double t, double dt) {
  const double r = t / dt;
  return std::abs(r - std::round(r)) < 1e-6 * std::max(1.0, r);
}

// Fixed steps must land on the sample times (as a run checks): say so before running anything.
void check_steps_divide_sampling(const AccuracyLadder& l) {
  if (std::none_of(l.methods.begin(), l.methods.end(),
                   [](const std::string& m) { return SolverSpec::fixed_step(m); }))
    return;
  for (double dt : l.dt_ms)
    for (double t : {l.scene.output.traces.every_ms, l.scene.output.traces.from_ms})
      if (!multiple_of(t, dt))
        throw ManifestError("--dt", fmt::format("a step of {:g} ms does not divide the trace sampling (every "
                                                "{:g} ms from {:g} ms); choose steps that do, or set --every",
                                                dt, l.scene.output.traces.every_ms, l.scene.output.traces.from_ms));
}

LadderOutcome run_once(const json& base, const json& solver, const std::shared_ptr<PluginRegistry>& registry) {
  json manifest = base;
  manifest["solver"] = solver;
  Scene scene = parse_scene(manifest);  // a bad manifest is the user's error
  scene.output.dir.clear();             // write nothing
  LadderOutcome o;
  Simulation simulation(scene, registry);
  try {
    simulation.run();
    o.completed = true;
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  const json summary = simulation.summary();
  o.wall_s = summary.value("wall_time_s", 0.0);
  o.steps = summary.value("steps", 0LL);
  o.cells = static_cast<long long>(simulation.tissue().cell_count());
  if (summary.contains("solver_choice")) {
    const json& c = summary["solver_choice"];
    o.chosen = c.value("method", std::string()) + " rtol " + fmt::format("{:.2g}", c.value("rtol", 0.0));
  }
  if (o.completed) o.record = record_of(simulation);
  return o;
}

// The reference, then the same at a 10x looser rtol measured against it (how
// good is the reference?).
void run_reference(AccuracyLadder& l, const std::shared_ptr<PluginRegistry>& registry,
                   const std::function<void(const std::string&)>& progress) {
  progress(fmt::format("reference: cvode rtol {:g}, atol {:g} ...", l.reference_rtol, l.reference_atol));
  l.reference = run_once(l.base, exact_cvode(l, l.reference_rtol), registry);
  if (!l.reference.completed)
    throw std::runtime_error("the reference run (CVODE rtol " + accuracy_number(l.reference_rtol) +
                             ") failed: " + l.reference.error);
  progress(fmt::format("reference: {:.3g} s wall, {} steps", l.reference.wall_s, l.reference.steps));
  l.check = run_once(l.base, exact_cvode(l, 10 * l.reference_rtol), registry);
  l.check_errors = l.check.completed ? compare_runs(l.reference.record, l.check.record) : AccuracyErrors{};
}

// One rung: the method at one setting, `repeat` times (the errors of the
// first run, the least wall time of all); a failed run ends the rung.
LadderRun run_rung(const AccuracyLadder& l, const std::string& method, double setting,
                   const std::shared_ptr<PluginRegistry>& registry) {
  LadderRun r;
  r.method = method;
  r.setting = setting;
  const json solver = solver_of(l.base, method, setting, l.atol_ratio);
  for (int k = 0; k < l.repeat; ++k) {
    LadderOutcome o = run_once(l.base, solver, registry);
    if (k == 0) {
      r.completed = o.completed;
      r.error = o.error;
      r.wall_s = o.wall_s;
      r.steps = o.steps;
      r.cells = o.cells;
      r.chosen = o.chosen;
      if (o.completed) r.errors = compare_runs(l.reference.record, o.record);
    } else {
      r.wall_s = std::min(r.wall_s, o.wall_s);
    }
    if (!o.completed) break;
  }
  return r;
}

const std::vector<double>& settings_of(const AccuracyLadder& l, const std::string& method) {
  return method == "cvode"      ? l.rtol
         : method == "adaptive" ? l.tol
         : method == "auto"     ? l.accuracy_ms
                                : l.dt_ms;
}

}  // namespace

std::string accuracy_number(double v, const char* spec) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format(fmt::runtime(spec), v);
}

std::string ladder_setting_text(const LadderRun& r) {
  if (r.method == "cvode") return fmt::format("rtol {:g}", r.setting);
  if (r.method == "adaptive") return fmt::format("tol {:g}", r.setting);
  if (r.method == "auto")
    return fmt::format("accuracy {:g} ms", r.setting) + (r.chosen.empty() ? "" : " (" + r.chosen + ")");
  return fmt::format("dt {:g} ms", r.setting);
}

AccuracyLadder plan_accuracy_ladder(const AccuracyLadderSpec& spec) {
  AccuracyLadder l;
  l.base = traced_v_alone(spec.manifest, spec.every_ms);
  l.methods = spec.methods.empty() ? kAllMethods : spec.methods;
  check_methods(l.methods);
  l.dt_ms = spec.dt_ms.empty() ? kDefaultDt_ms : spec.dt_ms;
  l.rtol = spec.rtol.empty() ? kDefaultRtol : spec.rtol;
  l.tol = spec.tol.empty() ? kDefaultTol : spec.tol;
  l.accuracy_ms = spec.accuracy_ms.empty() ? kDefaultAccuracy_ms : spec.accuracy_ms;
  check_ladders_positive(l);
  l.atol_ratio = spec.atol_ratio;
  l.reference_rtol =
      spec.reference_rtol > 0 ? spec.reference_rtol : *std::min_element(l.rtol.begin(), l.rtol.end()) / 100;
  l.reference_atol = l.reference_rtol * l.atol_ratio;
  l.repeat = std::max(1, spec.repeat);
  json checked = l.base;
  checked["solver"] = exact_cvode(l, l.reference_rtol);
  l.scene = parse_scene(checked);
  check_steps_divide_sampling(l);
  return l;
}

void run_accuracy_ladder(AccuracyLadder& l, const std::function<void(const std::string&)>& progress) {
  auto registry = std::make_shared<PluginRegistry>();
  run_reference(l, registry, progress);
  for (const auto& method : l.methods)
    for (double setting : settings_of(l, method)) {
      LadderRun r = run_rung(l, method, setting, registry);
      progress(fmt::format("{:<13} {:<14} {}", method, ladder_setting_text(r),
                           r.completed ? fmt::format("{:.3g} s, V RMS {} mV, APD90 {} ms", r.wall_s,
                                                     accuracy_number(r.errors.v_rms_mV),
                                                     accuracy_number(r.errors.apd90_max_ms))
                                       : "FAILED: " + r.error));
      l.runs.push_back(std::move(r));
    }
}

}  // namespace fibrodem
