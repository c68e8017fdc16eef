#include "study/accuracy_report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "io/csv_writer.hpp"
#include "io/plot_png.hpp"

namespace fibrodem {
namespace {

// Error levels of the "cheapest" table, in ms for APD90 and mV for V RMS.
constexpr double kLevels[] = {10, 1, 0.1, 0.01};

struct Level {
  std::string name;  // "APD90 error <= 1 ms"
  std::function<double(const AccuracyErrors&)> metric;
  double threshold;
};

std::vector<Level> error_levels(bool has_cv) {
  std::vector<Level> levels;
  for (double t : kLevels)
    levels.push_back({fmt::format("APD90 error <= {:g} ms", t), [](const AccuracyErrors& e) { return e.apd90_max_ms; }, t});
  for (double t : kLevels)
    levels.push_back({fmt::format("V RMS error <= {:g} mV", t), [](const AccuracyErrors& e) { return e.v_rms_mV; }, t});
  if (has_cv)
    for (double t : {0.05, 0.01, 0.001})
      levels.push_back({fmt::format("CV error <= {:g} %", 100 * t), [](const AccuracyErrors& e) { return e.cv_rel; }, t});
  return levels;
}

std::string list(const std::vector<double>& values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : ", ") + fmt::format("{:g}", v);
  return s;
}

void write_scene_and_reference(std::ostringstream& md, const AccuracyLadder& l) {
  const auto num = [](double v) { return accuracy_number(v); };
  const Scene& scene = l.scene;
  const auto& tr = scene.output.traces;
  const bool has_cv = l.has_cv();
  const double ref_cv = has_cv ? *l.reference.record.cv_cm_per_s : std::nan("");
  const AccuracyErrors& check_errors = l.check_errors;
  std::string traced;
  for (int c : tr.blocks.front().cells) traced += (traced.empty() ? "" : ", ") + std::to_string(c);
  md << fmt::format("- Scene: {} ms simulated, {} cells; V compared on cells [{}] every {:g} ms from {:g} ms; "
                    "biomarkers from {:g} ms.\n",
                    scene.duration_ms, l.reference.cells, traced, tr.every_ms, tr.from_ms, scene.output.biomarkers_from_ms);
  md << fmt::format("- **Reference: CVODE (BDF/Newton) at rtol {:g}, atol {:g}** (two orders tighter than the "
                    "tightest rtol on the ladder): {:.3g} s wall, {} steps.",
                    l.reference_rtol, l.reference_atol, l.reference.wall_s, l.reference.steps);
  if (has_cv) md << fmt::format(" Its CV: {:.4g} cm/s.", ref_cv);
  md << "\n";
  if (l.check.completed)
    md << fmt::format("- Reference check: CVODE at rtol {:g} differs from the reference by V RMS {} mV (max {} mV), "
                      "APD90 {} ms, activation {} ms{}: errors much below these are not resolved.\n",
                      10 * l.reference_rtol, num(check_errors.v_rms_mV), num(check_errors.v_max_mV),
                      num(check_errors.apd90_max_ms), num(check_errors.activation_max_ms),
                      has_cv ? ", CV " + num(check_errors.cv_abs_cm_per_s) + " cm/s" : std::string());
  else
    md << "- Reference check: CVODE at rtol " << num(10 * l.reference_rtol) << " failed: " << l.check.error << "\n";
  md << fmt::format("- Ladders (of the methods asked): fixed steps dt {} ms; CVODE rtol {} with atol = {:g} x rtol; "
                    "adaptive tol {} (rtol = atol); auto accuracy {} ms.\n",
                    list(l.dt_ms), list(l.rtol), l.atol_ratio, list(l.tol), list(l.accuracy_ms));
  md << "- Errors: V RMS and max over the compared cells and the sample times both runs share; APD90 and "
        "activation time: max |difference| over (cell, beat); `inf`: a beat (or its repolarisation, or the CV) "
        "present in the reference is missing in the run. Activation (max dV/dt) is located at the integrator's "
        "own steps, so activation and APD90 errors have a floor of about half the step near the upstroke.\n";
  md << fmt::format("- Wall time: Simulation::run on one thread (setup excluded), least of {} run(s), on a "
                    "machine that may be shared; cell-steps = cells x steps (CVODE: its internal steps, each "
                    "with Newton iterations).\n",
                    l.repeat);
}

void write_run_table(std::ostringstream& md, const AccuracyLadder& l) {
  const auto num = [](double v) { return accuracy_number(v); };
  const bool has_cv = l.has_cv();
  md << "\n| method | setting | status | wall s | cell-steps | V RMS mV | V max mV | APD90 err ms | activation err ms |"
     << (has_cv ? " CV err cm/s | CV rel err |" : "") << "\n";
  md << "|---|---|---|---|---|---|---|---|---|" << (has_cv ? "---|---|" : "") << "\n";
  for (const auto& r : l.runs) {
    md << "| " << r.method << " | " << ladder_setting_text(r) << " | " << (r.completed ? "ok" : "**failed**") << " | "
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
}

void write_cheapest_table(std::ostringstream& md, const AccuracyLadder& l) {
  const auto num = [](double v) { return accuracy_number(v); };
  const auto& runs = l.runs;
  md << "\n## Cheapest method for each error level\n\nThe completed run of least wall time meeting the level, "
        "overall and per method (its wall time in s); a run counts only if every finer run of its method "
        "(smaller dt or rtol) meets the level too, so that a lucky cancellation of errors does not.\n\n| error level | cheapest run | wall s |";
  for (const auto& m : l.methods) md << " " << m << " |";
  md << "\n|---|---|---|";
  for (std::size_t i = 0; i < l.methods.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& level : error_levels(l.has_cv())) {
    const auto best = cheapest_meeting(runs, level.metric, level.threshold);
    md << "| " << level.name << " | "
       << (best ? runs[*best].method + " " + ladder_setting_text(runs[*best]) : std::string("none")) << " | "
       << (best ? num(runs[*best].wall_s) : std::string("")) << " |";
    for (const auto& m : l.methods) {
      const auto b = cheapest_meeting(runs, level.metric, level.threshold, m);
      md << " " << (b ? ladder_setting_text(runs[*b]) + " (" + num(runs[*b].wall_s) + ")" : std::string("none"))
         << " |";
    }
    md << "\n";
  }
}

void write_failed_runs(std::ostringstream& md, const AccuracyLadder& l) {
  bool any_failed = false;
  for (const auto& r : l.runs)
    if (!r.completed) {
      if (!any_failed) md << "\n## Failed runs\n\n";
      any_failed = true;
      md << "- " << r.method << " " << ladder_setting_text(r) << ": " << r.error << "\n";
    }
}

// One panel of the work-precision plot: a metric against wall time, a series per method.
PlotPanel work_precision_panel(const AccuracyLadder& l, const std::string& title, const std::string& y_label,
                               const std::function<double(const AccuracyErrors&)>& metric, const std::string& unit) {
  PlotPanel p;
  p.title = title;
  p.x_label = "wall time (s)";
  p.y_label = y_label;
  for (const auto& m : l.methods) {
    PlotSeries s;
    s.label = m;
    for (const auto& r : l.runs)
      if (r.method == m && r.completed) {
        s.x.push_back(r.wall_s);
        s.y.push_back(metric(r.errors));
      }
    p.series.push_back(std::move(s));
  }
  for (double t : kLevels) p.guides.push_back({t, fmt::format("{:g} {}", t, unit)});
  return p;
}

}  // namespace

void write_accuracy_csv(const AccuracyLadder& l, const std::filesystem::path& file) {
  const double ref_cv = l.has_cv() ? *l.reference.record.cv_cm_per_s : std::nan("");
  CsvWriter csv(file, {"method", "dt_ms", "rtol", "atol", "status", "wall_s", "steps", "cells", "cell_steps",
                       "v_rms_mV", "v_max_mV", "v_samples", "apd90_err_ms", "activation_err_ms", "beats_compared",
                       "beats_mismatched", "cv_cm_per_s_reference", "cv_err_cm_per_s", "cv_rel_err", "error",
                       "accuracy_ms", "chosen"});
  auto row = [&](const std::string& method, double setting, const std::string& status, double wall, long long steps,
                 long long cells, const AccuracyErrors& e, const std::string& error, const std::string& chosen = "") {
    const bool cvode = method.rfind("cvode", 0) == 0;
    csv.cell(method);
    if (cvode) csv.cell(std::string()).cell(setting).cell(setting * l.atol_ratio);
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
  const LadderOutcome &reference = l.reference, &check = l.check;
  AccuracyErrors zero = compare_runs(reference.record, reference.record);
  row("cvode_reference", l.reference_rtol, "reference", reference.wall_s, reference.steps, reference.cells, zero, "");
  row("cvode_reference_check", 10 * l.reference_rtol, check.completed ? "completed" : "failed", check.wall_s,
      check.steps, check.cells, l.check_errors, check.error);
  for (const auto& r : l.runs)
    row(r.method, r.setting, r.completed ? "completed" : "failed", r.wall_s, r.steps, r.cells, r.errors, r.error,
        r.chosen);
}

std::string accuracy_markdown(const AccuracyLadder& l, const std::string& command) {
  std::ostringstream md;
  md << "# Accuracy against cost: " << l.scene.name << "\n\n";
  md << "`" << command << "`\n\n";
  write_scene_and_reference(md, l);
  write_run_table(md, l);
  write_cheapest_table(md, l);
  write_failed_runs(md, l);
  md << "\n![work-precision](work_precision.png)\n";
  return md.str();
}

void write_work_precision_png(const AccuracyLadder& l, const std::filesystem::path& file) {
  PlotOptions plot;
  plot.width_px = 1200;
  plot.height_px = 600;
  plot.title = fmt::format("{}: error against CVODE rtol {:g} vs. wall time (one thread)", l.scene.name,
                           l.reference_rtol);
  write_plot_png({work_precision_panel(l, "APD90 error (max over cells, beats)", "APD90 error (ms)",
                                       [](const AccuracyErrors& e) { return e.apd90_max_ms; }, "ms"),
                  work_precision_panel(l, "V error (RMS over cells, samples)", "V RMS error (mV)",
                                       [](const AccuracyErrors& e) { return e.v_rms_mV; }, "mV")},
                 file, plot);
}

std::string write_accuracy_report(const AccuracyLadder& l, const std::filesystem::path& dir,
                                  const std::string& command) {
  write_accuracy_csv(l, dir / "accuracy.csv");
  const std::string md = accuracy_markdown(l, command);
  std::ofstream(dir / "accuracy.md") << md;
  write_work_precision_png(l, dir / "work_precision.png");
  return md;
}

}  // namespace fibrodem
