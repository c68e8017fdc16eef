#include "study/restitution.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>

#include "io/csv_writer.hpp"
#include "io/plot_png.hpp"
#include "scene/scene.hpp"
#include "study/s1s2_protocol.hpp"
#include "study/worker_pool.hpp"
#include "util/manifest_error.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

const char* const kStudy = "the restitution protocol";

double median(std::vector<double> x) {
  if (x.empty()) return RestitutionPoint::kNone;
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

// One cell's beat, as biomarkers.csv gives it.
struct Beat {
  double activation_ms, rmp_mV, apo_mV, apd90_ms, apd50_ms;
};

}  // namespace

std::vector<double> default_restitution_intervals(const json& manifest) {
  const json& s1 = manifest.at("stimulus").at(0);
  const double period = number_at(s1, "period_ms", 0, "stimulus[0]");
  const double longest = period > 0 && number_at(s1, "count", 1, "stimulus[0]") > 1 ? period : 1000;
  std::vector<double> list = {1000, 800, 600, 500, 400, 350, 300};
  for (double ci = 275; ci >= 200; ci -= 25) list.push_back(ci);
  for (double ci = 190; ci >= 100; ci -= 10) list.push_back(ci);
  std::vector<double> intervals = {longest};
  for (double ci : list)
    if (ci < longest) intervals.push_back(ci);
  return intervals;
}

std::filesystem::path default_restitution_dir(const json& manifest) {
  return "out/restitution_" + manifest.value("name", std::string("scene"));
}

RestitutionPoint restitution_point(const CsvTable& biomarkers, std::size_t s1_beat, std::size_t s2_beat,
                                   const std::vector<int>& cells, double capture_fraction) {
  const char* names[] = {"cell", "type", "beat", "activation_ms", "rmp_mV", "apo_mV", "apd90_ms", "apd50_ms"};
  std::vector<std::size_t> col;
  for (const char* name : names) {
    const auto c = biomarkers.column(name);
    if (!c) throw std::runtime_error(std::string("biomarkers.csv has no column ") + name);
    col.push_back(*c);
  }
  const auto number = [](const std::string& text) {
    try {
      return text.empty() ? RestitutionPoint::kNone : std::stod(text);
    } catch (const std::exception&) {
      return RestitutionPoint::kNone;
    }
  };
  // S2 may cut the last S1 beat short of its repolarisation (a beat ends at
  // the next onset): then the S1 action potential is the one before, the
  // train's steady state.
  const std::size_t s1_before = s1_beat > 0 ? s1_beat - 1 : s1_beat;
  std::map<int, Beat> s1, s1_previous, s2;
  for (const auto& row : biomarkers.rows) {
    const int cell = std::stoi(row[col[0]]);
    const bool chosen = cells.empty() ? row[col[1]] == "myocyte"
                                      : std::find(cells.begin(), cells.end(), cell) != cells.end();
    const auto beat = static_cast<std::size_t>(std::stoll(row[col[2]]));
    if (!chosen || (beat != s1_beat && beat != s2_beat && beat != s1_before)) continue;
    const Beat b{number(row[col[3]]), number(row[col[4]]), number(row[col[5]]), number(row[col[6]]),
                 number(row[col[7]])};
    if (beat == s1_beat) s1[cell] = b;
    else if (beat == s2_beat) s2[cell] = b;
    else s1_previous[cell] = b;
  }
  RestitutionPoint p;
  std::vector<double> s1_apd90, s2_apd90, s2_apd50, di;
  for (auto [cell, a] : s1) {
    if (!std::isfinite(a.apd90_ms) && s1_previous.count(cell)) {
      const Beat& before = s1_previous.at(cell);
      // Fired, cut short by S2: the train's steady state stands in for its
      // APD. Not fired (a block of every other S1): the beat before was its
      // last action potential, and S2's interval counts from it.
      if (std::isfinite(a.activation_ms)) {
        a.apd90_ms = before.apd90_ms, a.rmp_mV = before.rmp_mV, a.apo_mV = before.apo_mV;
      } else {
        a = before;
      }
    }
    if (!std::isfinite(a.apd90_ms)) continue;  // S1 did not excite it: nothing to measure against
    ++p.cells_measured;
    const auto b = s2.find(cell);
    // S2 must fire the cell (an activation) to a measured APD90.
    if (b == s2.end() || !std::isfinite(b->second.activation_ms) || !std::isfinite(b->second.apd90_ms)) continue;
    if (b->second.apo_mV - b->second.rmp_mV < 0.5 * (a.apo_mV - a.rmp_mV)) continue;
    ++p.cells_captured;
    s1_apd90.push_back(a.apd90_ms);
    s2_apd90.push_back(b->second.apd90_ms);
    s2_apd50.push_back(b->second.apd50_ms);
    di.push_back(b->second.activation_ms - (a.activation_ms + a.apd90_ms));
  }
  p.captured = p.cells_measured > 0 && p.cells_captured >= capture_fraction * p.cells_measured;
  p.s1_apd90_ms = median(s1_apd90);
  p.s2_apd90_ms = median(s2_apd90);
  p.s2_apd50_ms = median(s2_apd50);
  p.di_ms = median(di);
  return p;
}

namespace {

struct Protocol {
  SweepFile sweep;  // its base: the manifest
  double s1_onset_ms = 0, tail_ms = 0;  // the last S1 onset; the run's length after S2
  RestitutionOptions options;
};

RestitutionPoint run_interval(const Protocol& protocol, double interval_ms) {
  const double onset = protocol.s1_onset_ms + interval_ms;
  SweepRun run;
  run.values = {{"stimulus[1].start_ms", onset}, {"duration_ms", onset + protocol.tail_ms}};
  const std::string folder = "runs/ci_" + interval_text(interval_ms) + "ms";
  run_sweep_point(protocol.sweep, run, protocol.options.out / folder, protocol.options.runner,
                  protocol.options.overwrite, protocol.options.report);
  RestitutionPoint p;
  if (run.status == "completed") {
    json manifest = protocol.sweep.base;
    manifest["stimulus"][1]["start_ms"] = onset;
    const auto s1_beat = beat_of_onset(manifest, protocol.s1_onset_ms), s2_beat = beat_of_onset(manifest, onset);
    const auto table = read_csv_table(protocol.options.out / folder / "biomarkers.csv");
    if (!table) {
      p.error = "no biomarkers.csv";
    } else if (s1_beat && s2_beat && *s1_beat != *s2_beat) {
      p = restitution_point(*table, *s1_beat, *s2_beat, protocol.options.cells, protocol.options.capture_fraction);
    } else {
      p.error = "S2 falls on an S1 onset";
    }
  } else {
    p.error = run.status + ": " + run.error;
  }
  p.interval_ms = interval_ms;
  p.run = folder;
  p.reused = run.reused;
  return p;
}

std::vector<RestitutionPoint> run_intervals(const Protocol& protocol, const std::vector<double>& intervals) {
  std::vector<RestitutionPoint> points(intervals.size());
  for_each_in_parallel(
      intervals.size(), protocol.options.jobs,
      [&](std::size_t i) { points[i] = run_interval(protocol, intervals[i]); },
      [&](std::size_t i) {
        if (protocol.options.on_run_done) protocol.options.on_run_done(points[i]);
      });
  return points;
}

void sort_by_interval(std::vector<RestitutionPoint>& points) {
  std::sort(points.begin(), points.end(),
            [](const RestitutionPoint& a, const RestitutionPoint& b) { return a.interval_ms > b.interval_ms; });
}

// The longest non-captured interval with a captured one above it (points by
// interval, decreasing), as indices (captured, not captured).
std::optional<std::pair<std::size_t, std::size_t>> erp_bracket(const std::vector<RestitutionPoint>& points) {
  for (std::size_t k = 0; k + 1 < points.size(); ++k)
    if (points[k].captured && !points[k + 1].captured) return std::make_pair(k, k + 1);
  return std::nullopt;
}

// Bisection between the bracket's intervals, one run a round, to the resolution.
void refine_erp(const Protocol& protocol, std::vector<RestitutionPoint>& points, RestitutionResult& result) {
  for (auto bracket = erp_bracket(points); bracket; bracket = erp_bracket(points)) {
    const double captured = points[bracket->first].interval_ms, failed = points[bracket->second].interval_ms;
    const double resolution = protocol.options.erp_resolution_ms;
    if (resolution <= 0 || captured - failed <= resolution + 1e-9) {
      result.erp_ms = failed;
      return;
    }
    RestitutionPoint p = run_interval(protocol, bisection_interval_ms(failed, captured, resolution));
    p.refinement = true;
    if (protocol.options.on_run_done) protocol.options.on_run_done(p);
    points.push_back(p);
    sort_by_interval(points);
  }
}

void write_table(const std::vector<RestitutionPoint>& points, const fs::path& file) {
  std::ofstream out(file);
  out << "interval_ms,captured,cells_measured,cells_captured,s1_apd90_ms,s2_apd90_ms,s2_apd50_ms,di_ms,stage,run\n";
  for (const auto& p : points) {
    out << interval_text(p.interval_ms) << "," << (p.captured ? 1 : 0) << "," << p.cells_measured << ","
        << p.cells_captured;
    for (double ms : {p.s1_apd90_ms, p.s2_apd90_ms, p.s2_apd50_ms, p.di_ms}) out << "," << format_number_or_empty(ms);
    out << "," << (p.refinement ? "bisection" : "scan") << "," << p.run << "\n";
  }
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

json result_json(const Protocol& protocol, const RestitutionResult& result) {
  json points = json::array();
  const auto or_null = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  for (const auto& p : result.points)
    points.push_back({{"interval_ms", p.interval_ms}, {"captured", p.captured}, {"di_ms", or_null(p.di_ms)},
                      {"s2_apd90_ms", or_null(p.s2_apd90_ms)}, {"s2_apd50_ms", or_null(p.s2_apd50_ms)},
                      {"s1_apd90_ms", or_null(p.s1_apd90_ms)}, {"run", p.run}, {"error", p.error}});
  return {{"s1_last_onset_ms", protocol.s1_onset_ms},
          {"capture_fraction", protocol.options.capture_fraction},
          {"erp_ms", result.erp_ms ? json(*result.erp_ms) : json(nullptr)},
          {"erp_resolution_ms", protocol.options.erp_resolution_ms},
          {"cells", protocol.options.cells.empty() ? json("myocytes") : json(protocol.options.cells)},
          {"points", points}};
}

// APD90 and APD50 against DI, and APD90 against the coupling interval.
void write_plot(const std::vector<RestitutionPoint>& points, const fs::path& file) {
  PlotPanel by_di{"S2 action potential against the diastolic interval", "DI [ms]", "APD [ms]", false, false, {}, {}};
  PlotPanel by_ci{"S2 APD90 against the S1-S2 coupling interval", "coupling interval [ms]", "APD90 [ms]",
                  false, false, {}, {}};
  PlotSeries apd90{"APD90", {}, {}}, apd50{"APD50", {}, {}}, ci{"APD90", {}, {}};
  for (auto it = points.rbegin(); it != points.rend(); ++it) {
    if (!it->captured) continue;
    apd90.x.push_back(it->di_ms), apd90.y.push_back(it->s2_apd90_ms);
    apd50.x.push_back(it->di_ms), apd50.y.push_back(it->s2_apd50_ms);
    ci.x.push_back(it->interval_ms), ci.y.push_back(it->s2_apd90_ms);
  }
  by_di.series = {apd90, apd50};
  by_ci.series = {ci};
  write_plot_png({by_di, by_ci}, file, PlotOptions{1200, 500, 15, "S1-S2 restitution", 0});
}

}  // namespace

RestitutionResult run_restitution(json manifest, RestitutionOptions options) {
  if (options.out.empty()) throw std::invalid_argument("run_restitution: no output folder");
  if (!(options.capture_fraction > 0 && options.capture_fraction <= 1))
    throw std::invalid_argument("the capture fraction must be in (0, 1]");
  parse_scene(manifest);  // a bad manifest is named before any run
  Protocol protocol;
  protocol.s1_onset_ms = last_s1_onset_ms(manifest, kStudy);
  const double s2_onset = number_at(manifest["stimulus"][1], "start_ms", 0, "stimulus[1]");
  const double duration_ms = number_at(manifest, "duration_ms", 0, "");
  protocol.tail_ms = duration_ms - s2_onset;
  if (!(protocol.tail_ms > 0))
    throw ManifestError("duration_ms", "the run must last past S2 (stimulus[1].start_ms " + interval_text(s2_onset) +
                                           " ms), got " + format_number_or_empty(duration_ms) + " ms");
  if (options.intervals_ms.empty()) options.intervals_ms = default_restitution_intervals(manifest);
  for (double ci : options.intervals_ms)
    if (!(ci > 0)) throw std::invalid_argument("coupling intervals must be > 0 ms, got " + format_number_or_empty(ci));
  protocol.sweep.base = manifest;
  protocol.options = options;
  fs::create_directories(options.out);
  RestitutionResult result;
  result.points = run_intervals(protocol, options.intervals_ms);
  sort_by_interval(result.points);
  refine_erp(protocol, result.points, result);
  write_table(result.points, options.out / "restitution.csv");
  std::ofstream(options.out / "restitution.json") << result_json(protocol, result).dump(2) << "\n";
  write_plot(result.points, options.out / "restitution.png");
  return result;
}

}  // namespace fibrodem
