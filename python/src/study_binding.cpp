// fibrodem._core.sweep, compare, vulnerable_window and restitution: the
// study layer's sweep, A/B comparison, vulnerable-window search and S1-S2
// restitution (the engines of `fibrodem sweep`, `compare`,
// `vulnerable-window` and `restitution`), run with the GIL released. The
// package (fibrodem/_study.py) turns their dicts into SweepResult and
// Comparison.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <csignal>
#include <filesystem>
#include <optional>

#include "binding.hpp"
#include "measure/summary_metrics.hpp"
#include "py_json.hpp"
#include "run/interrupt.hpp"
#include "scene/scene.hpp"
#include "study/compare_variants.hpp"
#include "study/study_options.hpp"
#include "study/sweep.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {

// Each entry "PATH=VALUE" (as --set) or a (path, value) pair.
std::vector<std::string> assignments(const py::list& overrides, const std::string& what) {
  std::vector<std::string> out;
  for (py::handle item : overrides) {
    if (py::isinstance<py::str>(item)) {
      out.push_back(item.cast<std::string>());
    } else if (py::isinstance<py::tuple>(item) && py::len(item) == 2 && py::isinstance<py::str>(item[py::int_(0)])) {
      const auto path = item[py::int_(0)].cast<std::string>();
      out.push_back(override_assignment(path, to_json(item[py::int_(1)], what + "[" + path + "]")));
    } else {
      throw py::type_error(what + ": each entry must be 'PATH=VALUE' or a (path, value) pair, not " +
                           std::string(py::str(py::type::of(item).attr("__name__"))));
    }
  }
  return out;
}

// A manifest given as a file path (str) or a dict.
json manifest_of(py::handle source, const std::string& what) {
  if (py::isinstance<py::str>(source)) return read_manifest_file(source.cast<std::string>());
  return to_json(source, what);
}

py::dict summary_statistics(const SampleSummary& s) {
  py::dict d;
  d["n"] = s.n, d["mean"] = s.mean, d["sd"] = s.sd, d["ci95_low"] = s.ci95_low, d["ci95_high"] = s.ci95_high;
  return d;
}

py::dict values_dict(const SweepValues& values) {
  py::dict d;
  for (const auto& [path, v] : values) d[py::str(path)] = to_python(v);
  return d;
}

py::dict sweep_dict(const SweepResult& result, const SweepFile& sweep) {
  const auto& metrics = summary_metrics();
  py::list names, runs, statistics;
  for (const auto& m : metrics) names.append(m.name);
  for (const auto& r : result.runs) {
    py::dict run, values;
    run["values"] = values_dict(r.values);
    for (const auto& m : metrics) values[py::str(m.name)] = m.of(r.summary);
    run["metrics"] = values;
    run["status"] = r.status, run["error"] = r.error, run["reused"] = r.reused;
    run["summary"] = to_python(r.summary);
    runs.append(run);
  }
  for (const auto& p : result.statistics) {
    py::dict point, of_metric;
    point["values"] = values_dict(p.values);
    point["completed"] = p.completed;
    for (std::size_t m = 0; m < metrics.size(); ++m) of_metric[py::str(metrics[m].name)] = summary_statistics(p.metrics[m]);
    point["metrics"] = of_metric;
    statistics.append(point);
  }
  py::dict d;
  d["out_dir"] = result.dir.string();
  d["markdown"] = result.markdown;
  d["metric_names"] = names;
  d["runs"] = runs;
  d["statistics"] = statistics;
  d["seeds"] = sweep.seeds;
  d["reused"] = result.reused;
  return d;
}

// The runs of a sweep or a search: child processes of `executable`, or, when
// it is empty, threads of this process with the plugins beside cli_dir().
PointRunner point_runner(const std::string& executable) {
  if (executable.empty()) return InProcessRunner{PluginRegistry::search_path_beside(cli_dir())};
  return ChildProcessRunner{executable};
}

// source: the sweep file's path (str) or its JSON (dict), whose manifest
// path is relative to `base_dir`, unless `manifest` (a dict) is given.
py::dict sweep(py::handle source, py::object manifest, const std::string& base_dir, const py::list& overrides,
               const std::string& out, unsigned jobs, bool overwrite, bool report, const std::string& executable,
               bool catch_sigint) {
  const std::vector<std::string> sets = assignments(overrides, "sweep(): set");
  SweepFile file;
  if (py::isinstance<py::str>(source)) {
    file = load_sweep_file(source.cast<std::string>(), sets);
  } else {
    const json given = manifest.is_none() ? json(nullptr) : to_json(manifest, "sweep(): the manifest");
    file = read_sweep(
        to_json(source, "sweep()"),
        [&](const std::string& name) {
          return given.is_null() ? read_manifest_file((std::filesystem::path(base_dir) / name).string()) : given;
        },
        sets);
  }
  SweepOptions options;
  options.out = out.empty() ? default_sweep_dir(file) : std::filesystem::path(out);
  options.jobs = jobs;
  options.overwrite = overwrite;
  options.report = report;
  options.runner = point_runner(executable);
  options.stop_requested = [] { return interrupt_signal() != 0; };
  SweepResult result;
  int stopped_by = 0;
  {
    py::gil_scoped_release release;
    std::optional<ScopedInterruptHandler> sigint;
    if (catch_sigint) sigint.emplace(SIGINT);
    result = run_sweep(file, options);
    stopped_by = interrupt_signal();
  }
  py::dict d = sweep_dict(result, file);
  d["interrupted"] = stopped_by != 0 ? py::object(py::str(signal_name(stopped_by))) : py::object(py::none());
  return d;
}

py::dict compare_result_dict(const CompareResult& r) {
  py::list rows, paired;
  for (const auto& row : r.rows) {
    py::dict d;
    d["type"] = row.type, d["metric"] = row.metric, d["a"] = row.a, d["b"] = row.b;
    d["b_minus_a"] = row.diff(), d["relative_diff"] = row.relative_diff();
    rows.append(d);
  }
  for (const auto& p : r.paired) {
    py::dict d;
    d["metric"] = p.metric, d["pairs"] = p.difference.n, d["a_mean"] = p.a_mean, d["b_mean"] = p.b_mean;
    d["b_minus_a_mean"] = p.difference.mean, d["b_minus_a_sd"] = p.difference.sd;
    d["ci95_low"] = p.difference.ci95_low, d["ci95_high"] = p.difference.ci95_high, d["t"] = p.t, d["p"] = p.p;
    paired.append(d);
  }
  py::list a, b;
  for (const auto& s : r.summaries_a) a.append(to_python(s));
  for (const auto& s : r.summaries_b) b.append(to_python(s));
  py::dict d;
  d["out_dir"] = r.dir.string();
  d["a_dir"] = (r.dir / r.a_dir).string();
  d["b_dir"] = (r.dir / r.b_dir).string();
  d["rows"] = rows;
  d["paired"] = paired;
  d["seeds"] = r.seeds;
  d["summaries_a"] = a;
  d["summaries_b"] = b;
  d["markdown"] = r.markdown;
  return d;
}

// As `fibrodem compare`: a and b are manifests (paths or dicts); b None: a
// again (then a_set or b_set makes the difference).
py::dict compare(py::handle a_source, py::handle b_source, const py::list& overrides, const py::list& a_overrides,
                 const py::list& b_overrides, const std::string& out, int seeds, bool overwrite, bool report,
                 bool console_log, bool catch_sigint) {
  const auto sets = assignments(overrides, "compare(): set");
  const auto a_sets = assignments(a_overrides, "compare(): a_set");
  const auto b_sets = assignments(b_overrides, "compare(): b_set");
  if (b_source.is_none() && a_sets.empty() && b_sets.empty())
    throw ManifestError("", "compare needs two manifests, or one manifest with a_set and b_set overrides");
  json a = manifest_of(a_source, "compare(): a");
  json b = b_source.is_none() ? a : manifest_of(b_source, "compare(): b");
  for (const auto& s : sets) apply_override(a, s), apply_override(b, s);
  for (const auto& s : a_sets) apply_override(a, s);
  for (const auto& s : b_sets) apply_override(b, s);
  CompareOptions options;
  options.out = out.empty() ? default_compare_dir(a) : std::filesystem::path(out);
  options.seeds = seeds;
  options.overwrite = overwrite;
  options.report = report;
  options.console_log = console_log;
  options.plugin_search_path = PluginRegistry::search_path_beside(cli_dir());
  CompareResult result;
  std::string stopped, failed;
  {
    py::gil_scoped_release release;
    std::optional<ScopedInterruptHandler> sigint;
    if (catch_sigint) sigint.emplace(SIGINT);
    try {
      result = run_compare(a, b, options);
    } catch (const InterruptedError& e) {
      stopped = e.what();
    } catch (const ManifestError&) {
      throw;
    } catch (const PluginError&) {
      throw;
    } catch (const std::exception& e) {
      failed = e.what();
    }
  }
  py::dict d = compare_result_dict(result);
  d["status"] = !stopped.empty() ? "interrupted" : !failed.empty() ? "failed" : "completed";
  d["message"] = !stopped.empty() ? stopped : failed;
  return d;
}

py::list windows_list(const std::vector<InducedWindow>& windows) {
  py::list out;
  for (const auto& w : windows) {
    py::dict d;
    d["lower_ms"] = w.lower_ms, d["upper_ms"] = w.upper_ms, d["open_below"] = w.open_below, d["open_above"] = w.open_above;
    out.append(d);
  }
  return out;
}

// As `fibrodem vulnerable-window`; from/to/step 0: the manifest's interval
// +- 100 ms by 10 ms. The runs run with the GIL released.
py::dict vulnerable_window(py::handle source, const py::list& overrides, const std::string& out, double from_ms,
                           double to_ms, double step_ms, double resolution_ms, int seeds, unsigned jobs,
                           double capture_fraction, bool overwrite, const std::string& executable) {
  StudyInput input{manifest_of(source, "vulnerable_window(): manifest"),
                   assignments(overrides, "vulnerable_window(): set"), out};
  VulnerableWindowOptions given;
  given.scan = {from_ms, to_ms, step_ms, resolution_ms};
  given.seeds = seeds;
  given.jobs = jobs;
  given.capture_fraction = capture_fraction;
  given.overwrite = overwrite;
  VulnerableWindowOptions options = prepare_vulnerable_window(input, given);
  options.runner = point_runner(executable);
  VulnerableWindowResult result;
  {
    py::gil_scoped_release release;
    result = run_vulnerable_window(input.manifest, options);
  }
  py::list runs, per_seed;
  for (const auto& r : result.search.results) {
    py::dict d;
    d["interval_ms"] = r.probe.interval_ms, d["seed"] = r.probe.seed, d["outcome"] = outcome_name(r.outcome);
    d["duration_ms"] = r.duration_ms ? py::object(py::float_(*r.duration_ms)) : py::object(py::none());
    d["ps_max"] = r.ps_max ? py::object(py::int_(*r.ps_max)) : py::object(py::none());
    d["stage"] = r.refinement ? "bisection" : "scan", d["run"] = (options.out / r.run).string();
    d["error"] = r.error, d["reused"] = r.reused;
    runs.append(d);
  }
  for (const auto& s : result.search.per_seed) {
    py::dict d;
    d["seed"] = s.seed, d["windows"] = windows_list(s.windows);
    per_seed.append(d);
  }
  py::dict d;
  d["out_dir"] = options.out.string();
  d["runs"] = runs;
  d["per_seed"] = per_seed;
  d["overall"] = windows_list(result.search.overall);
  d["reentry_output_added"] = result.reentry_output_added;
  d["reused"] = result.reused;
  return d;
}

// As `fibrodem restitution`; empty intervals: the default scan.
py::dict restitution(py::handle source, const py::list& overrides, const std::string& out,
                     const std::vector<double>& intervals_ms, const std::vector<int>& cells, double resolution_ms,
                     unsigned jobs, double capture_fraction, bool overwrite, const std::string& executable) {
  StudyInput input{manifest_of(source, "restitution(): manifest"), assignments(overrides, "restitution(): set"), out};
  RestitutionOptions given;
  given.intervals_ms = intervals_ms;
  given.cells = cells;
  given.erp_resolution_ms = resolution_ms;
  given.jobs = jobs;
  given.capture_fraction = capture_fraction;
  given.overwrite = overwrite;
  RestitutionOptions options = prepare_restitution(input, given);
  options.runner = point_runner(executable);
  RestitutionResult result;
  {
    py::gil_scoped_release release;
    result = run_restitution(input.manifest, options);
  }
  py::list points;
  for (const auto& p : result.points) {
    py::dict d;
    d["interval_ms"] = p.interval_ms, d["captured"] = p.captured, d["cells_measured"] = p.cells_measured;
    d["cells_captured"] = p.cells_captured, d["s1_apd90_ms"] = p.s1_apd90_ms, d["s2_apd90_ms"] = p.s2_apd90_ms;
    d["s2_apd50_ms"] = p.s2_apd50_ms, d["di_ms"] = p.di_ms, d["stage"] = p.refinement ? "bisection" : "scan";
    d["run"] = (options.out / p.run).string(), d["error"] = p.error, d["reused"] = p.reused;
    points.append(d);
  }
  py::dict d;
  d["out_dir"] = options.out.string();
  d["points"] = points;
  d["erp_ms"] = result.erp_ms ? py::object(py::float_(*result.erp_ms)) : py::object(py::none());
  return d;
}

}  // namespace

void bind_study(py::module_& m) {
  // The studies' defaults, as the command line's (study/study_options.hpp),
  // for the keywords of fibrodem.restitution and fibrodem.vulnerable_window.
  const RestitutionOptions restitution_defaults;
  const VulnerableWindowOptions window_defaults;
  m.attr("restitution_defaults") = py::dict(py::arg("resolution_ms") = restitution_defaults.erp_resolution_ms,
                                            py::arg("capture_fraction") = restitution_defaults.capture_fraction);
  m.attr("vulnerable_window_defaults") = py::dict(py::arg("resolution_ms") = window_defaults.scan.resolution_ms,
                                                  py::arg("capture_fraction") = window_defaults.capture_fraction);
  m.def("restitution", &restitution, py::arg("manifest"), py::arg("overrides"), py::arg("out"),
        py::arg("intervals_ms"), py::arg("cells"), py::arg("resolution_ms"), py::arg("jobs"),
        py::arg("capture_fraction"), py::arg("overwrite"), py::arg("executable"));
  m.def("vulnerable_window", &vulnerable_window, py::arg("manifest"), py::arg("overrides"), py::arg("out"),
        py::arg("from_ms"), py::arg("to_ms"), py::arg("step_ms"), py::arg("resolution_ms"), py::arg("seeds"),
        py::arg("jobs"), py::arg("capture_fraction"), py::arg("overwrite"), py::arg("executable"));
  m.def("sweep", &sweep, py::arg("source"), py::arg("manifest"), py::arg("base_dir"), py::arg("overrides"),
        py::arg("out"), py::arg("jobs"), py::arg("overwrite"), py::arg("report"), py::arg("executable"),
        py::arg("catch_sigint"));
  m.def("compare", &compare, py::arg("a"), py::arg("b"), py::arg("overrides"), py::arg("a_overrides"),
        py::arg("b_overrides"), py::arg("out"), py::arg("seeds"), py::arg("overwrite"), py::arg("report"),
        py::arg("console_log"), py::arg("catch_sigint"));
}

}  // namespace fibrodem::python
