// `fibrodem bench accuracy MANIFEST [--out DIR] [--set P=V]... [--methods ...]
//  [--dt LIST] [--rtol LIST] [--tol LIST] [--accuracy LIST] [--atol-ratio R]
//  [--reference-rtol X] [--every MS] [--repeat N]`: what accuracy costs in
// time (REFERENCES.md 4.4: Cooper, Spiteri & Mirams 2015 rank integrators by
// the largest step within an error).
//
// The scene is run with each integrator over a ladder: fixed-step methods
// (euler, rush_larsen, rush_larsen2) over steps dt, CVODE over relative
// tolerances (atol = ratio x rtol), adaptive over tolerances (rtol = atol =
// tol), auto over the APD90 accuracy asked (solver.accuracy). Each run is measured against a reference:
// CVODE at a relative tolerance two orders of magnitude tighter than the
// tightest on the ladder (core/measure/accuracy.hpp says how: V RMS and max over
// the traced cells and common sample times, APD90 and activation time max over
// cells and beats, CV absolute and relative). CVODE at 10x the reference's
// rtol, measured the same way, shows how far the reference itself is resolved.
// Both evaluate the exact model (solver.lookup_tables removed), so ladder runs
// with lookup tables are measured against the table-free solution.
// Runs are single-threaded and write nothing; the wall time is that of
// Simulation::run (setup excluded), the least of --repeat runs. A run that
// fails (blow-up) is reported as failed, with its error.
//
// Writes DIR/accuracy.csv (one row per run, the reference and its check
// first), DIR/accuracy.md (the table and the cheapest run meeting each error
// level: APD90 error 10, 1, 0.1, 0.01 ms; V RMS error 10, 1, 0.1, 0.01 mV; CV
// error 5, 1, 0.1 % when the scene has a CV) and DIR/work_precision.png (APD90
// and V RMS error against wall time, log-log).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "apps/commands.hpp"
#include "io/csv_writer.hpp"
#include "io/plot_png.hpp"
#include "measure/accuracy.hpp"
#include "run/run_record.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

const std::vector<std::string> kAllMethods = {"euler", "rush_larsen", "rush_larsen2", "cvode", "adaptive", "auto"};
const std::vector<double> kDefaultDt_ms = {0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.25};
const std::vector<double> kDefaultRtol = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
const std::vector<double> kDefaultTol = {1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 1e-4};
const std::vector<double> kDefaultAccuracy_ms = {1, 0.5, 0.1, 0.01};

// Error levels of the "cheapest" table, in ms for APD90 and mV for V RMS.
constexpr double kLevels[] = {10, 1, 0.1, 0.01};

struct Outcome {
  bool completed = false;
  std::string error;
  double wall_s = 0;
  long long steps = 0, cells = 0;
  std::string chosen;  // auto: the method it chose, with its settings
  RunRecord record;
};

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

Outcome run_once(const json& base, const json& solver, const std::shared_ptr<PluginRegistry>& registry) {
  json manifest = base;
  manifest["solver"] = solver;
  Scene scene = parse_scene(manifest);  // a bad manifest is the user's error: exit 2
  scene.output.dir.clear();             // write nothing
  Outcome o;
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

std::string num(double v, const char* spec = "{:.3g}") {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format(fmt::runtime(spec), v);
}

std::string setting_text(const LadderRun& r) {
  if (r.method == "cvode") return fmt::format("rtol {:g}", r.setting);
  if (r.method == "adaptive") return fmt::format("tol {:g}", r.setting);
  if (r.method == "auto")
    return fmt::format("accuracy {:g} ms", r.setting) + (r.chosen.empty() ? "" : " (" + r.chosen + ")");
  return fmt::format("dt {:g} ms", r.setting);
}

// Whether t is a whole multiple of dt (samples then fall on step ends).
bool multiple_of(double t, double dt) {
  const double r = t / dt;
  return std::abs(r - std::round(r)) < 1e-6 * std::max(1.0, r);
}

struct Level {
  std::string name;  // "APD90 error <= 1 ms"
  std::function<double(const AccuracyErrors&)> metric;
  double threshold;
};

}  // namespace

CLI::App* add_bench_accuracy_subcommand(CLI::App& bench, BenchAccuracyArgs& a) {
  auto* acc = bench.add_subcommand(
      "accuracy", "Error against a tight CVODE reference, and wall time, per integrator over ladders of dt and rtol");
  acc->add_option("manifest", a.manifest, "experiment manifest (JSON)")->required();
  acc->add_option("--out", a.out, "output directory (default out/accuracy_NAME)");
  acc->add_option("--set", a.overrides, "override a manifest value: PATH=VALUE (repeatable)");
  acc->add_option("--methods", a.methods, "integrators (default euler,rush_larsen,rush_larsen2,cvode,adaptive,auto)")
      ->delimiter(',');
  acc->add_option("--dt", a.dt_ms, "fixed-step ladder [ms] (default 0.001,0.002,0.005,0.01,0.02,0.05,0.1,0.25)")
      ->delimiter(',');
  acc->add_option("--rtol", a.rtol, "CVODE ladder (default 1e-3,1e-4,1e-5,1e-6,1e-7)")->delimiter(',');
  acc->add_option("--tol", a.tol, "adaptive ladder, rtol = atol (default 0.1,0.03,0.01,0.003,0.001,1e-4)")
      ->delimiter(',');
  acc->add_option("--accuracy", a.accuracy_ms, "auto ladder, solver.accuracy (default 1,0.5,0.1,0.01)")
      ->delimiter(',');
  acc->add_option("--atol-ratio", a.atol_ratio, "CVODE atol = ratio x rtol (default 1e-2)");
  acc->add_option("--reference-rtol", a.reference_rtol, "reference CVODE rtol (default: the tightest rtol / 100)");
  acc->add_option("--every", a.every_ms, "V sample interval [ms] (default: the manifest's output.traces.every_ms)");
  acc->add_option("--repeat", a.repeat, "runs per point; the wall time is the least (default 1)");
  return acc;
}

int bench_accuracy_command(const BenchAccuracyArgs& args) {
  return guarded([&]() -> int {
    json base = read_manifest_file(args.manifest);
    for (const auto& assignment : args.overrides) apply_override(base, assignment);
    // Only V is compared: trace it alone (on the manifest's cells), write nothing.
    if (!base.contains("output") || !base["output"].is_object()) base["output"] = json::object();
    base["output"].erase("dir");
    json& traces = base["output"]["traces"];
    if (traces.is_array() && !traces.empty()) traces = json(traces[0]);  // a list of blocks: V of the first block's cells
    if (!traces.is_object()) traces = json::object();
    traces["variables"] = json::array({"V"});
    if (args.every_ms > 0) traces["every_ms"] = args.every_ms;

    const std::vector<std::string> methods = args.methods.empty() ? kAllMethods : args.methods;
    for (const auto& m : methods)
      if (std::find(kAllMethods.begin(), kAllMethods.end(), m) == kAllMethods.end())
        throw ManifestError("--methods", "unknown method '" + m +
                                             "' (expected euler, rush_larsen, rush_larsen2, cvode, adaptive or auto)");
    const std::vector<double> dts = args.dt_ms.empty() ? kDefaultDt_ms : args.dt_ms;
    const std::vector<double> rtols = args.rtol.empty() ? kDefaultRtol : args.rtol;
    const std::vector<double> tols = args.tol.empty() ? kDefaultTol : args.tol;
    const std::vector<double> accuracies = args.accuracy_ms.empty() ? kDefaultAccuracy_ms : args.accuracy_ms;
    for (const auto& [values, option] : {std::pair{&dts, "--dt"}, std::pair{&rtols, "--rtol"},
                                         std::pair{&tols, "--tol"}, std::pair{&accuracies, "--accuracy"}})
      for (double v : *values)
        if (!(v > 0)) throw ManifestError(option, "expected positive values, got " + num(v));
    const double ref_rtol =
        args.reference_rtol > 0 ? args.reference_rtol : *std::min_element(rtols.begin(), rtols.end()) / 100;
    const double ref_atol = ref_rtol * args.atol_ratio;
    const int repeat = std::max(1, args.repeat);

    // The reference (and its check) evaluate the exact model: a ladder run with
    // solver.lookup_tables then shows the tables' error with the integrator's.
    auto exact_cvode = [&](double rtol) {
      json s = solver_of(base, "cvode", rtol, args.atol_ratio);
      s.erase("lookup_tables");
      return s;
    };
    const json ref_solver = exact_cvode(ref_rtol);
    json checked = base;
    checked["solver"] = ref_solver;
    const Scene scene = parse_scene(checked);
    // Fixed steps must land on the sample times (as a run checks): say so before running anything.
    if (std::any_of(methods.begin(), methods.end(),
                    [](const std::string& m) { return SolverSpec::fixed_step(m); }))
      for (double dt : dts)
        for (double t : {scene.output.traces.every_ms, scene.output.traces.from_ms})
          if (!multiple_of(t, dt))
            throw ManifestError("--dt", fmt::format("a step of {:g} ms does not divide the trace sampling (every "
                                                    "{:g} ms from {:g} ms); choose steps that do, or set --every",
                                                    dt, scene.output.traces.every_ms, scene.output.traces.from_ms));
    const std::filesystem::path dir = args.out.empty() ? "out/accuracy_" + scene.name : args.out;
    std::filesystem::create_directories(dir);

    auto registry = std::make_shared<PluginRegistry>();
    std::cerr << fmt::format("reference: cvode rtol {:g}, atol {:g} ...\n", ref_rtol, ref_atol);
    const Outcome reference = run_once(base, ref_solver, registry);
    if (!reference.completed) throw std::runtime_error("the reference run (CVODE rtol " + num(ref_rtol) + ") failed: " + reference.error);
    std::cerr << fmt::format("reference: {:.3g} s wall, {} steps\n", reference.wall_s, reference.steps);
    // How good is the reference? The same at a 10x looser rtol, measured against it.
    const Outcome check = run_once(base, exact_cvode(10 * ref_rtol), registry);
    const AccuracyErrors check_errors =
        check.completed ? compare_runs(reference.record, check.record) : AccuracyErrors{};

    std::vector<LadderRun> runs;
    for (const auto& method : methods) {
      const auto& settings = method == "cvode"      ? rtols
                             : method == "adaptive" ? tols
                             : method == "auto"     ? accuracies
                                                    : dts;
      for (double setting : settings) {
        LadderRun r;
        r.method = method;
        r.setting = setting;
        const json solver = solver_of(base, method, setting, args.atol_ratio);
        for (int k = 0; k < repeat; ++k) {
          Outcome o = run_once(base, solver, registry);
          if (k == 0) {
            r.completed = o.completed;
            r.error = o.error;
            r.wall_s = o.wall_s;
            r.steps = o.steps;
            r.cells = o.cells;
            r.chosen = o.chosen;
            if (o.completed) r.errors = compare_runs(reference.record, o.record);
          } else {
            r.wall_s = std::min(r.wall_s, o.wall_s);
          }
          if (!o.completed) break;
        }
        std::cerr << fmt::format("{:<13} {:<14} {}\n", method, setting_text(r),
                                 r.completed ? fmt::format("{:.3g} s, V RMS {} mV, APD90 {} ms", r.wall_s,
                                                           num(r.errors.v_rms_mV), num(r.errors.apd90_max_ms))
                                             : "FAILED: " + r.error);
        runs.push_back(std::move(r));
      }
    }

    // ---- accuracy.csv -------------------------------------------------------
    const bool has_cv = reference.record.cv_cm_per_s.has_value();
    const double ref_cv = has_cv ? *reference.record.cv_cm_per_s : std::nan("");
    {
      CsvWriter csv(dir / "accuracy.csv",
                    {"method", "dt_ms", "rtol", "atol", "status", "wall_s", "steps", "cells", "cell_steps",
                     "v_rms_mV", "v_max_mV", "v_samples", "apd90_err_ms", "activation_err_ms", "beats_compared",
                     "beats_mismatched", "cv_cm_per_s_reference", "cv_err_cm_per_s", "cv_rel_err", "error",
                     "accuracy_ms", "chosen"});
      auto row = [&](const std::string& method, double setting, const std::string& status, double wall,
                     long long steps, long long cells, const AccuracyErrors& e, const std::string& error,
                     const std::string& chosen = "") {
        const bool cvode = method.rfind("cvode", 0) == 0;
        csv.cell(method);
        if (cvode) csv.cell(std::string()).cell(setting).cell(setting * args.atol_ratio);
        else if (method == "adaptive") csv.cell(std::string()).cell(setting).cell(setting);
        else if (method == "auto") csv.cell(std::string()).cell(std::string()).cell(std::string());
        else csv.cell(setting).cell(std::string()).cell(std::string());
        csv.cell(status).cell(wall).cell(steps).cell(cells).cell(steps * cells);
        csv.cell(e.v_rms_mV).cell(e.v_max_mV).cell(e.v_samples).cell(e.apd90_max_ms).cell(e.activation_max_ms);
        csv.cell(static_cast<long long>(e.beats_compared)).cell(static_cast<long long>(e.beats_mismatched));
        csv.cell(ref_cv).cell(e.cv_abs_cm_per_s).cell(e.cv_rel).cell(error);
        if (method == "auto") csv.cell(setting);
        else csv.cell(std::string());
        csv.cell(chosen);
        csv.end_row();
      };
      AccuracyErrors zero = compare_runs(reference.record, reference.record);
      row("cvode_reference", ref_rtol, "reference", reference.wall_s, reference.steps, reference.cells, zero, "");
      row("cvode_reference_check", 10 * ref_rtol, check.completed ? "completed" : "failed", check.wall_s, check.steps,
          check.cells, check_errors, check.error);
      for (const auto& r : runs)
        row(r.method, r.setting, r.completed ? "completed" : "failed", r.wall_s, r.steps, r.cells, r.errors, r.error,
            r.chosen);
    }

    // ---- accuracy.md --------------------------------------------------------
    std::vector<Level> levels;
    for (double t : kLevels)
      levels.push_back({fmt::format("APD90 error <= {:g} ms", t), [](const AccuracyErrors& e) { return e.apd90_max_ms; }, t});
    for (double t : kLevels)
      levels.push_back({fmt::format("V RMS error <= {:g} mV", t), [](const AccuracyErrors& e) { return e.v_rms_mV; }, t});
    if (has_cv)
      for (double t : {0.05, 0.01, 0.001})
        levels.push_back({fmt::format("CV error <= {:g} %", 100 * t), [](const AccuracyErrors& e) { return e.cv_rel; }, t});

    std::ostringstream md;
    const auto& tr = scene.output.traces;
    std::string traced;
    for (int c : tr.blocks.front().cells) traced += (traced.empty() ? "" : ", ") + std::to_string(c);
    md << "# Accuracy against cost: " << scene.name << "\n\n";
    md << "`fibrodem bench accuracy " << args.manifest;
    for (const auto& o : args.overrides) md << " --set " << o;
    auto option = [&](const char* name, const std::vector<double>& values) {
      if (values.empty()) return;
      md << " " << name << " ";
      for (std::size_t i = 0; i < values.size(); ++i) md << (i ? "," : "") << fmt::format("{:g}", values[i]);
    };
    if (!args.methods.empty()) {
      md << " --methods ";
      for (std::size_t i = 0; i < args.methods.size(); ++i) md << (i ? "," : "") << args.methods[i];
    }
    option("--dt", args.dt_ms);
    option("--rtol", args.rtol);
    option("--tol", args.tol);
    option("--accuracy", args.accuracy_ms);
    if (args.reference_rtol > 0) md << fmt::format(" --reference-rtol {:g}", args.reference_rtol);
    if (args.every_ms > 0) md << fmt::format(" --every {:g}", args.every_ms);
    if (repeat > 1) md << " --repeat " << repeat;
    md << "`\n\n";
    md << fmt::format("- Scene: {} ms simulated, {} cells; V compared on cells [{}] every {:g} ms from {:g} ms; "
                      "biomarkers from {:g} ms.\n",
                      scene.duration_ms, reference.cells, traced, tr.every_ms, tr.from_ms, scene.output.biomarkers_from_ms);
    md << fmt::format("- **Reference: CVODE (BDF/Newton) at rtol {:g}, atol {:g}** (two orders tighter than the "
                      "tightest rtol on the ladder): {:.3g} s wall, {} steps.",
                      ref_rtol, ref_atol, reference.wall_s, reference.steps);
    if (has_cv) md << fmt::format(" Its CV: {:.4g} cm/s.", ref_cv);
    md << "\n";
    if (check.completed)
      md << fmt::format("- Reference check: CVODE at rtol {:g} differs from the reference by V RMS {} mV (max {} mV), "
                        "APD90 {} ms, activation {} ms{}: errors much below these are not resolved.\n",
                        10 * ref_rtol, num(check_errors.v_rms_mV), num(check_errors.v_max_mV),
                        num(check_errors.apd90_max_ms), num(check_errors.activation_max_ms),
                        has_cv ? ", CV " + num(check_errors.cv_abs_cm_per_s) + " cm/s" : std::string());
    else
      md << "- Reference check: CVODE at rtol " << num(10 * ref_rtol) << " failed: " << check.error << "\n";
    auto list = [](const std::vector<double>& values) {
      std::string s;
      for (double v : values) s += (s.empty() ? "" : ", ") + fmt::format("{:g}", v);
      return s;
    };
    md << fmt::format("- Ladders (of the methods asked): fixed steps dt {} ms; CVODE rtol {} with atol = {:g} x rtol; "
                      "adaptive tol {} (rtol = atol); auto accuracy {} ms.\n",
                      list(dts), list(rtols), args.atol_ratio, list(tols), list(accuracies));
    md << "- Errors: V RMS and max over the compared cells and the sample times both runs share; APD90 and "
          "activation time: max |difference| over (cell, beat); `inf`: a beat (or its repolarisation, or the CV) "
          "present in the reference is missing in the run. Activation (max dV/dt) is located at the integrator's "
          "own steps, so activation and APD90 errors have a floor of about half the step near the upstroke.\n";
    md << fmt::format("- Wall time: Simulation::run on one thread (setup excluded), least of {} run(s), on a "
                      "machine that may be shared; cell-steps = cells x steps (CVODE: its internal steps, each "
                      "with Newton iterations).\n",
                      repeat);
    md << "\n| method | setting | status | wall s | cell-steps | V RMS mV | V max mV | APD90 err ms | activation err ms |"
       << (has_cv ? " CV err cm/s | CV rel err |" : "") << "\n";
    md << "|---|---|---|---|---|---|---|---|---|" << (has_cv ? "---|---|" : "") << "\n";
    for (const auto& r : runs) {
      md << "| " << r.method << " | " << setting_text(r) << " | " << (r.completed ? "ok" : "**failed**") << " | "
         << num(r.wall_s) << " | " << fmt::format("{:.3g}", static_cast<double>(r.cell_steps())) << " | ";
      if (r.completed) {
        md << num(r.errors.v_rms_mV) << " | " << num(r.errors.v_max_mV) << " | " << num(r.errors.apd90_max_ms)
           << " | " << num(r.errors.activation_max_ms) << " |";
        if (has_cv) md << " " << num(r.errors.cv_abs_cm_per_s) << " | " << num(r.errors.cv_rel) << " |";
      } else {
        md << " |  |  |  |" << (has_cv ? "  |  |" : "");
      }
      md << "\n";
    }

    md << "\n## Cheapest method for each error level\n\nThe completed run of least wall time meeting the level, "
          "overall and per method (its wall time in s); a run counts only if every finer run of its method "
          "(smaller dt or rtol) meets the level too, so that a lucky cancellation of errors does not.\n\n| error level | cheapest run | wall s |";
    for (const auto& m : methods) md << " " << m << " |";
    md << "\n|---|---|---|";
    for (std::size_t i = 0; i < methods.size(); ++i) md << "---|";
    md << "\n";
    for (const auto& level : levels) {
      const auto best = cheapest_meeting(runs, level.metric, level.threshold);
      md << "| " << level.name << " | "
         << (best ? runs[*best].method + " " + setting_text(runs[*best]) : std::string("none")) << " | "
         << (best ? num(runs[*best].wall_s) : std::string("")) << " |";
      for (const auto& m : methods) {
        const auto b = cheapest_meeting(runs, level.metric, level.threshold, m);
        md << " " << (b ? setting_text(runs[*b]) + " (" + num(runs[*b].wall_s) + ")" : std::string("none")) << " |";
      }
      md << "\n";
    }
    bool any_failed = false;
    for (const auto& r : runs)
      if (!r.completed) {
        if (!any_failed) md << "\n## Failed runs\n\n";
        any_failed = true;
        md << "- " << r.method << " " << setting_text(r) << ": " << r.error << "\n";
      }
    md << "\n![work-precision](work_precision.png)\n";
    std::ofstream(dir / "accuracy.md") << md.str();

    // ---- work_precision.png ---------------------------------------------------
    auto panel = [&](const std::string& title, const std::string& y_label, auto metric, const std::string& unit) {
      PlotPanel p;
      p.title = title;
      p.x_label = "wall time (s)";
      p.y_label = y_label;
      for (const auto& m : methods) {
        PlotSeries s;
        s.label = m;
        for (const auto& r : runs)
          if (r.method == m && r.completed) {
            s.x.push_back(r.wall_s);
            s.y.push_back(metric(r.errors));
          }
        p.series.push_back(std::move(s));
      }
      for (double t : kLevels) p.guides.push_back({t, fmt::format("{:g} {}", t, unit)});
      return p;
    };
    PlotOptions plot;
    plot.width_px = 1200;
    plot.height_px = 600;
    plot.title = fmt::format("{}: error against CVODE rtol {:g} vs. wall time (one thread)", scene.name, ref_rtol);
    write_plot_png({panel("APD90 error (max over cells, beats)", "APD90 error (ms)",
                          [](const AccuracyErrors& e) { return e.apd90_max_ms; }, "ms"),
                    panel("V error (RMS over cells, samples)", "V RMS error (mV)",
                          [](const AccuracyErrors& e) { return e.v_rms_mV; }, "mV")},
                   dir / "work_precision.png", plot);

    std::cout << md.str() << "\noutputs: " << dir.string() << "/{accuracy.csv,accuracy.md,work_precision.png}\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
