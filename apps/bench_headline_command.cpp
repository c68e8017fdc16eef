// `fibrodem bench headline [--baseline OTHER] [--repeat N] [--examples DIR]
//  [--skip-em] [--large]`: the speed figures users ask about, in one table, each as a
// ratio to another build measured in the same run (machines are shared and
// noisy: only ratios taken side by side mean much).
//
// Figures, from this build and from OTHER (a `fibrodem` executable, e.g. the
// previous release), alternating, the median of N rounds:
//   - Google Benchmark figures of `fibrodem bench`: the Rush-Larsen step of
//     10^4 colman and courtemanche cells on one thread, without and with
//     lookup tables (cell-steps/s), one
//     simulated second of one CRN cell under CVODE at (rtol, atol) = (1e-6,
//     1e-8) and (1e-4, 1e-6) (ms), one DEM step of the Fig. 3 in-series tissue
//     (particle-steps/s, one thread); and the colman step on one thread
//     alone and on two independent threads (no shared work): their ratio is
//     the most 2 threads can gain on this machine at the time (the ceiling
//     beside the scenes' gains);
//   - with --large, the first 30 ms of examples/scale/sheet_5cm.json;
//   - whole runs of the paper's Fig. 3 scenes at their manifests' settings
//     (examples/fig3_in_series_ep.json and _em.json, 500 ms, Rush-Larsen
//     0.01 ms; without their settle before t = 0) and with solver.method "auto" (which a build without it
//     cannot run): wall time and where it went (summary.json
//     wall_time_by_process_s); and the two at their settings on one thread,
//     for the gain from threads (one thread's time over the default's).
// Each figure is read from the programs' own output (--benchmark_format=json,
// summary.json); a figure the other build lacks is shown as "-".
#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <unistd.h>

#include "apps/commands.hpp"
#include "scene/scene.hpp"
#include "util/json_reader.hpp"
#include "util/number_text.hpp"

namespace fibrodem::cli {

namespace fs = std::filesystem;

namespace {

// The machine's ceiling for the gain from threads: colman on one thread
// alone and on each of two independent threads.
constexpr const char* kAloneBenchmark = "rush_larsen_step_1e4_each_thread/colman/real_time/threads:1";
constexpr const char* kIndependentBenchmark = "rush_larsen_step_1e4_each_thread/colman/real_time/threads:2";

struct Micro {
  std::string label, benchmark, counter;  // counter empty: the time per iteration [ms]
};

const std::vector<Micro> kMicro = {
    {"colman Rush-Larsen step, 1 thread [M cell-steps/s]", "rush_larsen_step_1e4/colman", "cell_steps_per_s"},
    {"colman Rush-Larsen step with lookup tables, 1 thread [M cell-steps/s]", "rush_larsen_step_1e4_lut/colman",
     "cell_steps_per_s"},
    {"courtemanche Rush-Larsen step, 1 thread [M cell-steps/s]", "rush_larsen_step_1e4/courtemanche",
     "cell_steps_per_s"},
    {"courtemanche Rush-Larsen step with lookup tables, 1 thread [M cell-steps/s]",
     "rush_larsen_step_1e4_lut/courtemanche", "cell_steps_per_s"},
    {"CRN 1 s, CVODE rtol 1e-6 atol 1e-8 [ms]", "one_cell_1s/courtemanche/cvode_rtol1e-6", ""},
    {"CRN 1 s, CVODE rtol 1e-4 atol 1e-6 [ms]", "one_cell_1s/courtemanche/cvode_rtol1e-4", ""},
    {"DEM step, Fig. 3 in-series, 1 thread [M particle-steps/s]", "dem_step/in_series", "particle_steps_per_s"},
    {"colman Rush-Larsen step, 10^4 cells on 1 thread alone [M cell-steps/s]", kAloneBenchmark, "cell_steps_per_s"},
    {"colman Rush-Larsen step, 10^4 cells on each of 2 independent threads [M cell-steps/s, sum]",
     kIndependentBenchmark, "cell_steps_per_s"},
};

// The row of kMicro that holds `benchmark`.
std::size_t micro_row(const std::string& benchmark) {
  return static_cast<std::size_t>(std::find_if(kMicro.begin(), kMicro.end(),
                                               [&](const Micro& m) { return m.benchmark == benchmark; }) -
                                  kMicro.begin());
}

// Runs `command` with its standard output to `file`; false if it failed.
bool run_to_file(const std::string& command, const fs::path& file) {
  return std::system((command + " > '" + file.string() + "' 2>/dev/null").c_str()) == 0;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// name -> figure, from one `bench --benchmark_format=json` run of `program`.
std::map<std::string, double> micro_figures(const std::string& program, const fs::path& scratch) {
  std::string filter;
  for (const auto& m : kMicro) filter += (filter.empty() ? "" : "|") + m.benchmark;
  const fs::path out = scratch / "bench.json";
  std::map<std::string, double> figures;
  if (!run_to_file(quoted(program) + " bench --benchmark_format=json --benchmark_min_time=0.5 '--benchmark_filter=^(" +
                       filter + ")(/real_time)?$'",
                   out))
    return figures;
  json report;
  try {
    report = json::parse(std::ifstream(out));
  } catch (const std::exception&) {
    return figures;
  }
  for (const auto& b : report.value("benchmarks", json::array()))
    for (const auto& m : kMicro) {
      const std::string name = b.value("name", "");
      if (name != m.benchmark && name != m.benchmark + "/real_time") continue;
      if (m.counter.empty()) {
        const double scale = b.value("time_unit", "ns") == "ms" ? 1.0 : b.value("time_unit", "ns") == "us" ? 1e-3 : 1e-6;
        figures[m.benchmark] = b.value("real_time", 0.0) * scale;
      } else if (b.contains(m.counter)) {
        figures[m.benchmark] = b[m.counter].get<double>() / 1e6;
      }
    }
  return figures;
}

struct Scene {
  std::string label;
  fs::path manifest;
  std::string options;     // more command-line options of the run
  int one_thread_of = -1;  // this is scene k on one thread: their ratio is the gain from threads
};

// summary.json of one run of a scene by `program` (empty if it failed).
// The scene's manifest without its tissue settle (the manifest key
// `settle`): the figures are those of the run from t = 0, and a build that
// predates the key runs the same scene.
fs::path unsettled_copy(const fs::path& manifest, const fs::path& scratch) {
  json m = read_manifest_file(manifest.string());
  m.erase("settle");
  const fs::path copy = scratch / manifest.filename();
  std::ofstream(copy) << m.dump(2);
  return copy;
}

json scene_summary(const std::string& program, const Scene& scene, const fs::path& scratch) {
  const fs::path out = scratch / "run";
  fs::remove_all(out);
  const fs::path manifest = unsettled_copy(scene.manifest, scratch);
  if (!run_to_file(quoted(program) + " run " + quoted(manifest.string()) + " " + scene.options +
                       " --quiet --out " + quoted(out.string()),
                   scratch / "run.txt"))
    return json();
  try {
    return json::parse(std::ifstream(out / "summary.json"));
  } catch (const std::exception&) {
    return json();
  }
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Row {
  std::string label;
  std::vector<double> ours, theirs;
  bool rate = false;  // higher is better (a throughput), else a time
};

// Figures more than this much worse than the baseline are named after the
// table: a slow-down of 5 % or more is not to be read as the machine's noise.
constexpr double kWorseBy = 0.05;

// How much worse this build is than the baseline (0.12: 12 % slower), or 0.
double worse_by(const Row& r, double ours, double theirs) {
  if (!(ours > 0 && theirs > 0)) return 0;
  return std::max(0.0, r.rate ? theirs / ours - 1 : ours / theirs - 1);
}

std::string cell(double v) { return std::isfinite(v) ? significant_digits(v, 3) : "-"; }

}  // namespace

CLI::App* add_bench_headline_subcommand(CLI::App& bench, BenchHeadlineArgs& a) {
  auto* head = bench.add_subcommand("headline", "The headline speed figures (kernels, Fig. 3 scenes, CVODE, DEM), "
                                                "each beside another build's, measured in one run");
  head->add_option("--baseline", a.baseline, "another fibrodem executable to measure alongside (e.g. the previous build)");
  head->add_option("--repeat", a.repeat, "rounds, alternating the builds; figures are medians (default 3)");
  head->add_option("--examples", a.examples, "folder of the Fig. 3 manifests (default: examples)");
  head->add_flag("--skip-em", a.skip_em, "leave out the electromechanical scene (the longest)");
  head->add_flag("--large", a.large,
                 "add the 846,279-cell sheet (examples/scale/sheet_5cm.json, its first 30 ms: ~2 min a run)");
  return head;
}

int bench_headline_command(const BenchHeadlineArgs& args) {
  return guarded([&]() -> int {
    const std::string self = boost::dll::program_location().string();
    if (!args.baseline.empty() && !fs::exists(args.baseline))
      throw ManifestError("--baseline", "no such executable: " + args.baseline);
    const std::string automatic = "--set 'solver={\"method\":\"auto\"}'";
    const fs::path ep = fs::path(args.examples) / "fig3_in_series_ep.json",
                   em = fs::path(args.examples) / "fig3_in_series_em.json";
    const std::string one_thread = "--set solver.threads=1";
    std::vector<Scene> scenes = {{"Fig. 3 in-series EP, 500 ms", ep, ""},
                                 {"Fig. 3 in-series EP, 500 ms, 1 thread", ep, one_thread, 0},
                                 {"Fig. 3 in-series EP, 500 ms, solver auto", ep, automatic}};
    if (!args.skip_em) {
      const int em_at = static_cast<int>(scenes.size());
      scenes.push_back({"Fig. 3 in-series EM, 500 ms", em, ""});
      scenes.push_back({"Fig. 3 in-series EM, 500 ms, 1 thread", em, one_thread, em_at});
      scenes.push_back({"Fig. 3 in-series EM, 500 ms, solver auto", em, automatic});
    }
    // The large sheet as shipped, cut to the front's entry (30 ms: set-up,
    // 2 snapshots, ~880 adaptive steps): where a million-cell second spends
    // its time, per cell-step.
    if (args.large)
      scenes.push_back({"sheet 5 cm (846,279 cells), first 30 ms, auto",
                        fs::path(args.examples) / "scale" / "sheet_5cm.json", "--set duration_ms=30"});
    for (const auto& scene : scenes)
      if (!fs::exists(scene.manifest))
        throw ManifestError("--examples", "no " + scene.manifest.string() + " (run from the repository root)");

    const fs::path scratch = fs::temp_directory_path() / fmt::format("fibrodem_headline_{}", getpid());
    fs::create_directories(scratch);
    std::vector<Row> rows;
    for (const auto& m : kMicro) rows.push_back({m.label, {}, {}, !m.counter.empty()});
    for (const auto& scene : scenes) rows.push_back({scene.label + ": wall time [s]", {}, {}, false});
    std::map<std::string, std::map<std::string, std::vector<double>>> breakdown;  // scene -> process -> s (ours)

    const int rounds = std::max(1, args.repeat);
    for (int round = 0; round < rounds; ++round) {
      std::cerr << "round " << round + 1 << " of " << rounds << "\n";
      for (int side = 0; side < (args.baseline.empty() ? 1 : 2); ++side) {
        const std::string& program = side == 0 ? self : args.baseline;
        const auto figures = micro_figures(program, scratch);
        for (std::size_t i = 0; i < kMicro.size(); ++i) {
          const auto it = figures.find(kMicro[i].benchmark);
          if (it != figures.end()) (side == 0 ? rows[i].ours : rows[i].theirs).push_back(it->second);
        }
        for (std::size_t s = 0; s < scenes.size(); ++s) {
          const json summary = scene_summary(program, scenes[s], scratch);
          if (!summary.is_object() || summary.value("status", "") != "completed") continue;
          (side == 0 ? rows[kMicro.size() + s].ours : rows[kMicro.size() + s].theirs)
              .push_back(summary["wall_time_s"].get<double>());
          if (side == 0)
            for (const auto& [process, seconds] : summary["wall_time_by_process_s"].items())
              breakdown[scenes[s].label][process].push_back(seconds.get<double>());
        }
      }
    }
    fs::remove_all(scratch);

    std::cout << "| figure | this build |" << (args.baseline.empty() ? "" : " baseline | this / baseline |") << "\n"
              << "|---|---|" << (args.baseline.empty() ? "" : "---|---|") << "\n";
    for (const auto& r : rows) {
      const double ours = median(r.ours), theirs = median(r.theirs);
      std::cout << "| " << r.label << " | " << cell(ours) << " |";
      if (!args.baseline.empty()) std::cout << " " << cell(theirs) << " | " << cell(ours / theirs) << " |";
      std::cout << "\n";
    }
    if (!args.baseline.empty()) {
      std::string worse;
      for (const auto& r : rows)
        if (const double w = worse_by(r, median(r.ours), median(r.theirs)); w > kWorseBy)
          worse += fmt::format("\n- {}: {:.1f} % worse", r.label, 100 * w);
      std::cout << "\nFigures more than " << 100 * kWorseBy << " % worse than the baseline:"
                << (worse.empty() ? " none" : worse) << "\n";
    }
    // The gain from threads, per round (a round's two runs of one build are
    // taken minutes apart at most): "median (round 1, round 2, ...)".
    auto gains = [](const std::vector<double>& one_s, const std::vector<double>& all_s) {
      std::vector<double> g;
      std::string each;
      for (std::size_t k = 0; k < std::min(one_s.size(), all_s.size()); ++k) {
        g.push_back(one_s[k] / all_s[k]);
        each += (k ? ", " : "") + cell(g.back());
      }
      return g.empty() ? std::string("-") : cell(median(g)) + " (" + each + ")";
    };
    // The machine's ceiling: independent threads' throughput over one's (a
    // rate, so the ratio is the other way up).
    const std::size_t alone = micro_row(kAloneBenchmark), independent = micro_row(kIndependentBenchmark);
    std::cout << "\nTwo independent threads' colman throughput over one thread's (this machine's ceiling for the "
                 "gain from 2 threads, median of the rounds' ratios, and each round's): this build "
              << gains(rows[independent].ours, rows[alone].ours);
    if (!args.baseline.empty())
      std::cout << ", baseline " << gains(rows[independent].theirs, rows[alone].theirs);
    std::cout << "\n";
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      if (scenes[s].one_thread_of < 0) continue;
      const Row& one = rows[kMicro.size() + s];
      const Row& all = rows[kMicro.size() + static_cast<std::size_t>(scenes[s].one_thread_of)];
      std::cout << "\n" << scenes[static_cast<std::size_t>(scenes[s].one_thread_of)].label
                << ", one thread's wall time over the default's (median of the rounds' ratios, and each round's): this build "
                << gains(one.ours, all.ours);
      if (!args.baseline.empty()) std::cout << ", baseline " << gains(one.theirs, all.theirs);
      std::cout << "\n";
    }
    for (const auto& [scene, processes] : breakdown) {
      std::cout << "\n" << scene << ", this build, wall time by process [s, median]:";
      for (const auto& [process, seconds] : processes) std::cout << " " << process << " " << cell(median(seconds)) << ";";
      std::cout << "\n";
    }
    std::cout << fmt::format("\n{} round(s); figures are medians; machine: {} cores.\n", rounds,
                             sysconf(_SC_NPROCESSORS_ONLN));
    return 0;
  });
}

}  // namespace fibrodem::cli
