#include "study/vulnerable_window.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>

#include "io/plot_png.hpp"
#include "report/vulnerable_window_report.hpp"
#include "scene/scene.hpp"
#include "study/s1s2_protocol.hpp"
#include "study/worker_pool.hpp"
#include "util/manifest_error.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

const char* outcome_name(S2Outcome outcome) {
  switch (outcome) {
    case S2Outcome::reentry: return "reentry";
    case S2Outcome::no_reentry: return "no_reentry";
    case S2Outcome::no_capture: return "no_capture";
    case S2Outcome::failed: return "failed";
  }
  return "failed";
}

// ---- The search ----

std::vector<double> scan_intervals(const WindowScan& scan) {
  if (!(scan.step_ms > 0)) throw std::invalid_argument("the scan's step must be > 0 ms");
  if (!(scan.to_ms >= scan.from_ms)) throw std::invalid_argument("the scan's end is before its start");
  if (!(scan.resolution_ms > 0)) throw std::invalid_argument("the bisection's resolution must be > 0 ms");
  const double n = std::floor((scan.to_ms - scan.from_ms) / scan.step_ms + 1e-9) + 1;
  if (n > 1e4) throw std::invalid_argument("the scan has more than 10^4 intervals: take a larger step");
  std::vector<double> intervals;
  for (int k = 0; k < static_cast<int>(n); ++k) intervals.push_back(scan.from_ms + k * scan.step_ms);
  return intervals;
}

std::vector<InducedWindow> induced_windows(std::vector<S2Result> results, const WindowScan& scan) {
  std::sort(results.begin(), results.end(),
            [](const S2Result& a, const S2Result& b) { return a.probe.interval_ms < b.probe.interval_ms; });
  std::vector<InducedWindow> windows;
  for (std::size_t k = 0; k < results.size(); ++k) {
    if (!induced(results[k].outcome)) continue;
    std::size_t last = k;
    while (last + 1 < results.size() && induced(results[last + 1].outcome)) ++last;
    InducedWindow w;
    w.lower_ms = results[k].probe.interval_ms;
    w.upper_ms = results[last].probe.interval_ms;
    w.open_below = k == 0 && w.lower_ms <= scan.from_ms;
    w.open_above = last + 1 == results.size() && w.upper_ms >= scan.to_ms - 1e-9;
    windows.push_back(w);
    k = last;
  }
  return windows;
}

namespace {

// A boundary of one seed still to be refined: `low` and `high` classified
// differently, nothing classified between them.
struct Bracket {
  long long seed;
  double low_ms, high_ms;
};

// Adjacent classified intervals of one seed on either side of a boundary,
// wider apart than the resolution.
std::vector<Bracket> open_brackets(const std::map<long long, std::map<double, bool>>& known, double resolution_ms) {
  std::vector<Bracket> brackets;
  for (const auto& [seed, by_interval] : known)
    for (auto it = by_interval.begin(); it != by_interval.end() && std::next(it) != by_interval.end(); ++it) {
      const auto next = std::next(it);
      if (it->second != next->second && next->first - it->first > resolution_ms + 1e-9)
        brackets.push_back({seed, it->first, next->first});
    }
  return brackets;
}

// The intervals induced on at least one seed: the seeds' windows merged where
// they overlap or lie within the resolution of each other (the seeds' probes
// differ, so the windows are merged as ranges, not probe by probe).
std::vector<InducedWindow> union_of_windows(const std::vector<SeedWindows>& per_seed, double resolution_ms) {
  std::vector<InducedWindow> all;
  for (const auto& s : per_seed) all.insert(all.end(), s.windows.begin(), s.windows.end());
  std::sort(all.begin(), all.end(), [](const InducedWindow& a, const InducedWindow& b) { return a.lower_ms < b.lower_ms; });
  std::vector<InducedWindow> merged;
  for (const auto& w : all) {
    if (!merged.empty() && w.lower_ms <= merged.back().upper_ms + resolution_ms + 1e-9) {
      InducedWindow& m = merged.back();
      if (w.upper_ms > m.upper_ms) m.open_above = w.open_above;
      else if (w.upper_ms == m.upper_ms) m.open_above = m.open_above || w.open_above;
      m.upper_ms = std::max(m.upper_ms, w.upper_ms);
      m.open_below = m.open_below || w.open_below;
    } else {
      merged.push_back(w);
    }
  }
  return merged;
}

}  // namespace

WindowSearch search_vulnerable_window(const WindowScan& scan, const std::vector<long long>& seeds,
                                      const S2Classifier& classify) {
  if (seeds.empty()) throw std::invalid_argument("the search needs at least one tissue seed");
  WindowSearch search;
  std::map<long long, std::map<double, bool>> known;  // seed -> interval -> induced
  auto take = [&](std::vector<S2Probe> probes, bool refinement) {
    std::vector<S2Result> results = classify(probes);
    if (results.size() != probes.size()) throw std::logic_error("the classifier must return one result per probe");
    for (auto& r : results) {
      r.refinement = refinement;
      known[r.probe.seed][r.probe.interval_ms] = induced(r.outcome);
      search.results.push_back(std::move(r));
    }
  };
  std::vector<S2Probe> scan_probes;
  for (long long seed : seeds)
    for (double interval : scan_intervals(scan)) scan_probes.push_back({interval, seed});
  take(scan_probes, false);
  // Each round halves every bracket: log2(step / resolution) rounds.
  for (auto brackets = open_brackets(known, scan.resolution_ms); !brackets.empty();
       brackets = open_brackets(known, scan.resolution_ms)) {
    std::vector<S2Probe> probes;
    for (const auto& b : brackets) probes.push_back({bisection_interval_ms(b.low_ms, b.high_ms, scan.resolution_ms), b.seed});
    take(probes, true);
  }
  for (long long seed : seeds) {
    std::vector<S2Result> mine;
    for (const auto& r : search.results)
      if (r.probe.seed == seed) mine.push_back(r);
    search.per_seed.push_back({seed, induced_windows(mine, scan)});
  }
  search.overall = union_of_windows(search.per_seed, scan.resolution_ms);
  return search;
}

// ---- Running fibrodem ----

namespace {
const char* const kStudy = "the vulnerable-window search";
}

WindowScan default_scan(const json& manifest) {
  const double interval = coupling_interval_ms(manifest, kStudy);
  WindowScan scan;
  scan.step_ms = 10;
  scan.from_ms = std::max(10.0, interval - 100);
  scan.to_ms = std::max(scan.from_ms, interval + 100);
  return scan;
}

std::filesystem::path default_vulnerable_window_dir(const json& manifest) {
  return "out/vulnerable_window_" + manifest.value("name", std::string("scene"));
}

bool ensure_reentry_output(json& manifest) {
  if (!manifest.contains("output") || manifest["output"].is_null()) manifest["output"] = json::object();
  if (manifest["output"].contains("reentry")) return false;
  manifest["output"]["reentry"] = {{"every_ms", 2}, {"tau_ms", 10}};
  return true;
}

S2Outcome classify_summary(const json& summary, double s2_onset_ms, double capture_fraction) {
  if (!summary.is_object() || summary.value("status", "") != "completed") return S2Outcome::failed;
  const json& reentry = summary.value("reentry", json(nullptr));
  if (!reentry.is_object()) return S2Outcome::failed;
  if (reentry.value("detected", false)) return S2Outcome::reentry;
  // S2's beat: the one that starts at its onset (manifest as run).
  const json& manifest = summary.value("manifest", json(nullptr));
  if (!manifest.is_object()) return S2Outcome::no_reentry;
  const auto beat = beat_of_onset(manifest, s2_onset_ms);
  if (!beat) return S2Outcome::no_reentry;
  for (const auto& b : reentry.value("unreached_fraction_per_beat", json::array()))
    if (b.value("beat", -1) == static_cast<long long>(*beat) && b.contains("fraction") && b["fraction"].is_number())
      return 1 - b["fraction"].get<double>() < capture_fraction ? S2Outcome::no_capture : S2Outcome::no_reentry;
  return S2Outcome::no_reentry;  // the beat was not measured: capture cannot be told
}

namespace {

// What every run of the search shares.
struct SearchRuns {
  SweepFile sweep;          // its base: the manifest (output.reentry ensured)
  double s1_onset_ms = 0;   // the last onset of S1
  double s2_onset_ms = 0, duration_ms = 0;  // the manifest's own
  bool seeded = false;
  VulnerableWindowOptions options;
};

std::string run_folder(const S2Probe& p) {
  return "runs/ci_" + interval_text(p.interval_ms) + "ms_seed_" + std::to_string(p.seed);
}

// One interval: S2 moved, and the run as long after S2 as the manifest's.
S2Result run_probe(const SearchRuns& search, const S2Probe& probe) {
  const double onset = search.s1_onset_ms + probe.interval_ms;
  SweepRun point;
  point.values = {{"stimulus[1].start_ms", onset}, {"duration_ms", search.duration_ms - search.s2_onset_ms + onset}};
  if (search.seeded) point.values.push_back({"seed", probe.seed});
  S2Result result;
  result.probe = probe;
  result.run = run_folder(probe);
  run_sweep_point(search.sweep, point, search.options.out / result.run, search.options.runner,
                  search.options.overwrite, search.options.report);
  result.outcome = classify_summary(point.summary, onset, search.options.capture_fraction);
  if (point.status != "completed") result.error = point.status + ": " + point.error;
  if (point.summary.is_object() && point.summary.contains("reentry") && point.summary["reentry"].is_object()) {
    const json& r = point.summary["reentry"];
    if (r.contains("duration_ms") && r["duration_ms"].is_number()) result.duration_ms = r["duration_ms"].get<double>();
    if (r.contains("phase_singularities_max") && r["phase_singularities_max"].is_number())
      result.ps_max = r["phase_singularities_max"].get<int>();
  }
  result.reused = point.reused;
  return result;
}

// A batch on a pool of workers, results in the probes' order.
std::vector<S2Result> run_batch(const SearchRuns& search, const std::vector<S2Probe>& probes) {
  std::vector<S2Result> results(probes.size());
  for_each_in_parallel(
      probes.size(), search.options.jobs, [&](std::size_t i) { results[i] = run_probe(search, probes[i]); },
      [&](std::size_t i) {
        if (search.options.on_run_done) search.options.on_run_done(results[i]);
      });
  return results;
}

std::string optional_text(const std::optional<double>& x) { return x ? significant_digits(*x, 10) : ""; }

void write_table(const WindowSearch& search, const fs::path& file) {
  std::ofstream out(file);
  out << "interval_ms,seed,outcome,duration_ms,ps_max,stage,run\n";
  std::vector<S2Result> rows = search.results;
  std::stable_sort(rows.begin(), rows.end(), [](const S2Result& a, const S2Result& b) {
    return a.probe.seed != b.probe.seed ? a.probe.seed < b.probe.seed : a.probe.interval_ms < b.probe.interval_ms;
  });
  for (const auto& r : rows)
    out << interval_text(r.probe.interval_ms) << "," << r.probe.seed << "," << outcome_name(r.outcome) << ","
        << optional_text(r.duration_ms) << "," << (r.ps_max ? std::to_string(*r.ps_max) : "") << ","
        << (r.refinement ? "bisection" : "scan") << "," << r.run << "\n";
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

json windows_json(const std::vector<InducedWindow>& windows) {
  json out = json::array();
  for (const auto& w : windows)
    out.push_back({{"lower_ms", w.lower_ms}, {"upper_ms", w.upper_ms}, {"open_below", w.open_below},
                   {"open_above", w.open_above}});
  return out;
}

json search_json(const SearchRuns& runs, const VulnerableWindowResult& result) {
  const WindowScan& scan = runs.options.scan;
  json j = {{"scan", {{"from_ms", scan.from_ms}, {"to_ms", scan.to_ms}, {"step_ms", scan.step_ms},
                      {"resolution_ms", scan.resolution_ms}}},
            {"s1_last_onset_ms", runs.s1_onset_ms},
            {"capture_fraction", runs.options.capture_fraction},
            {"runs", result.search.results.size()},
            {"failed", std::count_if(result.search.results.begin(), result.search.results.end(),
                                     [](const S2Result& r) { return r.outcome == S2Outcome::failed; })},
            {"overall", windows_json(result.search.overall)}};
  j["per_seed"] = json::array();
  for (const auto& s : result.search.per_seed) j["per_seed"].push_back({{"seed", s.seed}, {"windows", windows_json(s.windows)}});
  if (result.reentry_output_added)
    j["note"] = "the manifest had no output.reentry: added with every_ms 2, tau_ms 10";
  return j;
}

// Outcome (0 failed, 1 no capture, 2 no re-entry, 3 re-entry) against the
// interval, one series per seed; re-entry's duration in a second panel.
void write_plot(const WindowSearch& search, const fs::path& file) {
  PlotPanel outcome{"outcome of S2 (0 failed, 1 no capture, 2 no re-entry, 3 re-entry)", "S1-S2 coupling interval [ms]",
                    "outcome", false, false, {}, {}};
  PlotPanel duration{"activity after S2", "S1-S2 coupling interval [ms]", "duration [ms]", false, false, {}, {}};
  for (const auto& s : search.per_seed) {
    std::vector<S2Result> mine;
    for (const auto& r : search.results)
      if (r.probe.seed == s.seed) mine.push_back(r);
    std::sort(mine.begin(), mine.end(),
              [](const S2Result& a, const S2Result& b) { return a.probe.interval_ms < b.probe.interval_ms; });
    PlotSeries o{"seed " + std::to_string(s.seed), {}, {}}, d = o;
    for (const auto& r : mine) {
      o.x.push_back(r.probe.interval_ms);
      o.y.push_back(r.outcome == S2Outcome::reentry ? 3 : r.outcome == S2Outcome::no_reentry ? 2
                    : r.outcome == S2Outcome::no_capture ? 1 : 0);
      d.x.push_back(r.probe.interval_ms);
      d.y.push_back(r.duration_ms ? *r.duration_ms : std::nan(""));
    }
    outcome.series.push_back(std::move(o));
    duration.series.push_back(std::move(d));
  }
  write_plot_png({outcome, duration}, file, PlotOptions{1200, 500, 15, "vulnerable window", 0});
}

}  // namespace

VulnerableWindowResult run_vulnerable_window(json manifest, VulnerableWindowOptions options) {
  if (options.out.empty()) throw std::invalid_argument("run_vulnerable_window: no output folder");
  if (!(options.capture_fraction >= 0 && options.capture_fraction <= 1))
    throw std::invalid_argument("the capture fraction must be in [0, 1]");
  VulnerableWindowResult result;
  result.reentry_output_added = ensure_reentry_output(manifest);
  parse_scene(manifest);  // a bad manifest is named before any run
  SearchRuns runs;
  runs.s1_onset_ms = last_s1_onset_ms(manifest, kStudy);
  runs.s2_onset_ms = number_at(manifest["stimulus"][1], "start_ms", 0, "stimulus[1]");
  runs.duration_ms = number_at(manifest, "duration_ms", 0, "");
  if (!(runs.duration_ms > runs.s2_onset_ms))
    throw ManifestError("duration_ms", "the run must last past S2 (stimulus[1].start_ms " +
                                           interval_text(runs.s2_onset_ms) + " ms), got " +
                                           interval_text(runs.duration_ms) + " ms");
  if (options.scan.step_ms <= 0) {
    const double resolution = options.scan.resolution_ms;
    options.scan = default_scan(manifest);
    options.scan.resolution_ms = resolution;
  }
  if (!(options.scan.from_ms > 0)) throw std::invalid_argument("the scan's intervals must be > 0 ms");
  std::vector<long long> seeds = {manifest.value("seed", 0LL)};
  runs.seeded = options.seeds > 0;
  for (int k = 1; k < options.seeds; ++k) seeds.push_back(seeds.front() + k);
  runs.sweep.base = manifest;
  runs.options = options;
  fs::create_directories(options.out);
  result.search = search_vulnerable_window(options.scan, seeds,
                                           [&](const std::vector<S2Probe>& probes) { return run_batch(runs, probes); });
  for (const auto& r : result.search.results) result.reused += r.reused;
  write_table(result.search, options.out / "vulnerable_window.csv");
  std::ofstream(options.out / "vulnerable_window.json") << search_json(runs, result).dump(2) << "\n";
  write_plot(result.search, options.out / "vulnerable_window.png");
  write_vulnerable_window_report(options.out);
  return result;
}

}  // namespace fibrodem
