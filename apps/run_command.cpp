// `fibrodem run` and `fibrodem validate`.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/mpi_ranks.hpp"
#include "apps/openmp_spinning.hpp"
#include "report/run_report.hpp"
#include "report/vulnerable_window_report.hpp"
#include "run/interrupt.hpp"
#include "run/over_ranks.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

// The scene of the manifest with its overrides; a scene that may run on a
// team of threads restarts the program first (apps/openmp_spinning.hpp).
Scene load_scene(const RunArgs& args) {
  json manifest = read_manifest_file(args.manifest);
  for (const auto& assignment : args.overrides) apply_override(manifest, assignment);
  Scene scene = parse_scene(manifest);
  if (may_use_thread_team(scene, manifest)) bound_openmp_spinning();
  return scene;
}

// What a finished run left in its folder, as one line: every file and folder
// at its top (report.html, maps/, snapshots/ and checkpoints/ among them when
// the scene asked for them), so the line never names a file that was not
// written, nor leaves out one that was.
void print_outputs(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error))
    names.push_back(entry.path().filename().string() + (entry.is_directory() ? "/" : ""));
  std::sort(names.begin(), names.end());
  std::cout << "outputs: " << dir.string() << "/{";
  for (std::size_t i = 0; i < names.size(); ++i) std::cout << (i ? "," : "") << names[i];
  std::cout << "}\n";
}

// Under mpirun with several ranks, a scene they cannot share stops on every
// rank before anything is written, instead of N processes writing one folder.
void refuse_split_over_ranks(const std::string& command, const Scene& scene) {
  const int ranks = MpiRanks::launched_size();
  if (ranks <= 1) return;
  const std::vector<std::string> unsupported = unsupported_over_ranks(scene);
  if (!unsupported.empty()) throw std::runtime_error(refusal_over_ranks(command, ranks, unsupported));
}

// The ranks of an mpirun that splits this run's tissue (null: one process).
std::unique_ptr<MpiRanks> split_ranks(const std::string& command) {
  const int launched = MpiRanks::launched_size();
  if (launched <= 1) return nullptr;
  auto ranks = std::make_unique<MpiRanks>();
  if (!ranks->launched())
    throw std::runtime_error("`fibrodem " + command + "` under mpirun with " + std::to_string(launched) +
                             " ranks: this fibrodem was built without MPI, so its ranks cannot share one tissue. "
                             "Nothing was written. Run it on one rank, or build with libopenmpi-dev "
                             "(scripts/setup.sh)");
  return ranks;
}

// A run split over ranks. SIGINT and SIGTERM stop every rank at the same
// step (the run agrees on it over the ranks), with every output written, as
// in one process. A rank that fails ends the job, after writing summary.json
// if it is not rank 0 (Simulation): the others would wait for it.
template <class Run>
void run_split(MpiRanks& ranks, const std::filesystem::path& dir, Run&& run) {
  install_interrupt_handlers();
  try {
    run();
  } catch (const InterruptedError&) {
    if (ranks.rank() == 0) print_outputs(dir);
    throw;
  } catch (const std::exception& e) {
    print_failure("error", e.what());  // (names the rank)
    ranks.abort(4);
  }
  if (ranks.rank() == 0) print_outputs(dir);
}

}  // namespace

int run_command(const RunArgs& args) {
  return guarded([&] {
    Scene scene = load_scene(args);
    if (!args.out.empty()) scene.output.dir = args.out;
    if (scene.output.dir.empty()) scene.output.dir = "out/" + scene.name;
    scene.output.overwrite = args.overwrite;
    if (args.no_report) scene.output.report = false;
    refuse_split_over_ranks("run", scene);
    const std::unique_ptr<MpiRanks> ranks = split_ranks("run");
    RunOptions options;
    options.console_log = !args.quiet;
    // A progress line only for a person at a terminal, never in logs or CI.
    options.progress = !args.quiet && isatty(STDERR_FILENO) && std::getenv("CI") == nullptr;
    if (!ranks) {
      Simulation simulation(scene, nullptr, options);
      install_interrupt_handlers();  // SIGINT / SIGTERM end the run at the end of a step, outputs kept
      simulation.run();
      print_outputs(scene.output.dir);
      return 0;
    }
    // The tissue split over the ranks (docs/guide/parallel.md); rank 0 writes.
    options.ranks = ranks->group();
    run_split(*ranks, scene.output.dir, [&] {
      Simulation simulation(scene, nullptr, options);
      simulation.run();
    });
    return 0;
  });
}

// The run in `dir` again, from its summary.json's manifest, continued from
// its newest checkpoint that reads back whole (or from t = 0 if none does).
int resume_command(const ResumeArgs& args) {
  return guarded([&] {
    const std::filesystem::path dir = args.dir;
    std::ifstream in(dir / "summary.json");
    if (!in) throw ManifestError("", args.dir + " holds no run to resume (no summary.json)");
    json summary;
    try {
      summary = json::parse(in);
    } catch (const json::exception& e) {
      throw ManifestError("", (dir / "summary.json").string() + " cannot be read: " + e.what());
    }
    const std::string status = summary.value("status", std::string());
    if (status == "completed") throw ManifestError("", "the run in " + args.dir + " completed: nothing to resume");
    if (!summary.contains("manifest")) throw ManifestError("", (dir / "summary.json").string() + " has no manifest");
    Scene scene = parse_scene(summary.at("manifest"));
    refuse_split_over_ranks("resume", scene);
    if (may_use_thread_team(scene, summary.at("manifest"))) bound_openmp_spinning();
    scene.output.dir = args.dir;
    scene.output.overwrite = true;  // its own files
    if (args.no_report) scene.output.report = false;
    // Split over ranks: over as many as the checkpoint's, each rank reads its
    // own part of it; over another number, every part (Simulation::resume).
    const std::unique_ptr<MpiRanks> ranks = split_ranks("resume");
    const bool tells = !ranks || ranks->rank() == 0;
    RunOptions options;
    options.console_log = !args.quiet;
    options.progress = !args.quiet && isatty(STDERR_FILENO) && std::getenv("CI") == nullptr;
    if (ranks) options.ranks = ranks->group();
    Simulation simulation(scene, nullptr, options);
    auto search = latest_good_checkpoint(dir);
    for (const auto& skipped : search.skipped)
      if (tells) std::cerr << "passed over " << skipped << "\n";
    if (search.found) {
      if (tells)
        std::cerr << "resuming " << args.dir << " (" << status << ") from " << search.found->file.string() << "\n";
      simulation.resume_from(std::move(*search.found));
    } else if (tells) {
      std::cerr << "no usable checkpoint in " << args.dir << ": the run starts again from t = 0\n";
    }
    if (!ranks) {
      install_interrupt_handlers();
      simulation.run();
      print_outputs(args.dir);
      return 0;
    }
    run_split(*ranks, args.dir, [&] { simulation.run(); });
    return 0;
  });
}

// report.html of a run's folder as it is on disk (run/report_run).
int report_command(const ReportArgs& args) {
  return guarded([&] {
    const std::filesystem::path dir = args.dir;
    if (!std::filesystem::is_directory(dir)) throw ManifestError("", args.dir + " is not a folder");
    if (std::filesystem::exists(dir / "sweep.csv"))
      throw ManifestError("", args.dir + " is a sweep's folder: `fibrodem sweep` writes its report.html (run the "
                                         "same command again: completed runs are kept, not run again)");
    if (std::filesystem::exists(dir / "comparison.csv"))
      throw ManifestError("", args.dir + " is a comparison's folder: `fibrodem compare` writes its report.html");
    if (is_vulnerable_window_folder(dir)) {
      std::cout << "report: " << write_vulnerable_window_report(dir).string() << "\n";
      return 0;
    }
    if (!std::filesystem::exists(dir / "summary.json") && !std::filesystem::exists(dir / "run.log"))
      throw ManifestError("", args.dir + " holds no run (neither summary.json nor run.log)");
    std::cout << "report: " << write_run_report(dir).string() << "\n";
    return 0;
  });
}

// Under mpirun, the scene split as `run` would split it: each rank's memory
// (its own cells, rank 0 also what it gathers and writes) on a line of its own.
int validate_command(const RunArgs& args) {
  return guarded([&] {
    Scene scene = load_scene(args);
    scene.output.dir.clear();  // validating writes nothing
    refuse_split_over_ranks("validate", scene);
    const std::unique_ptr<MpiRanks> ranks = split_ranks("validate");
    RunOptions options;
    if (ranks) options.ranks = ranks->group();
    Simulation simulation(scene, nullptr, options);  // builds tissue, loads plugins, checks names; does not run
    const std::vector<std::string> estimates =
        ranks ? ranks->gather(simulation.resource_estimate()) : std::vector<std::string>{simulation.resource_estimate()};
    if (ranks && ranks->rank() != 0) return 0;
    const Tissue& tissue = simulation.tissue();
    std::cout << args.manifest << ": valid. " << tissue.cell_count() << " cells ("
              << tissue.count(CellType::myocyte) << " myocytes, " << tissue.count(CellType::fibroblast)
              << " fibroblasts); processes:";
    for (const auto& p : simulation.processes().built) std::cout << " " << p.name;
    std::cout << "; " << simulation.integrator_description() << "; ";
    if (!ranks) {
      std::cout << estimates[0] << "\n";
      return 0;
    }
    std::cout << "split over " << ranks->size() << " MPI ranks, each rank's estimate:\n";
    for (std::size_t r = 0; r < estimates.size(); ++r) std::cout << "  rank " << r << ": " << estimates[r] << "\n";
    return 0;
  });
}

}  // namespace fibrodem::cli
