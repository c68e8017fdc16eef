// `fibrodem sweep SWEEP.json [--out DIR] [--jobs N] [--set P=V]...`: runs a
// manifest over the Cartesian product of parameter values (and tissue seeds)
// and tabulates the results (sweep_table.hpp).
//
// (The sweep file: scene/sweep_file.hpp.)
// Runs go to DIR/run_<k>/, each a `fibrodem run` process of its own
// (single-threaded, so the numbers are those of a lone run): a run that
// crashes (a segfault in a user's plugin) cannot take the others down; its
// status is "crashed" with the signal, or "failed" with its error.
// Resumable: a run whose folder holds a completed summary.json of the same
// manifest (its manifest.json, byte for byte) is not run again.
// Past one machine: under `mpirun -n N`, run k goes to rank k mod N (each
// rank a local pool of workers), and rank 0 writes the tables: the same
// numbers as a local sweep.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/dll/runtime_symbol_info.hpp>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "apps/commands.hpp"
#include "apps/mpi_ranks.hpp"
#include "apps/sweep_table.hpp"
#include "io/csv_writer.hpp"
#include "run/simulation.hpp"
#include "scene/sweep_file.hpp"

namespace fibrodem::cli {

namespace {

// The last line a run printed to its standard error (its error, when it
// stopped before writing a summary), else `otherwise`.
std::string last_line(const std::filesystem::path& file, const std::string& otherwise) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last.empty() ? otherwise : last;
}

// The summary of a completed run of exactly this manifest in dir, if there is one.
json completed_before(const std::filesystem::path& dir, const std::string& manifest_text) {
  std::ifstream manifest(dir / "manifest.json"), summary(dir / "summary.json");
  if (!manifest || !summary) return nullptr;
  std::ostringstream text;
  text << manifest.rdbuf();
  if (text.str() != manifest_text) return nullptr;
  const json s = json::parse(summary, nullptr, /*allow_exceptions=*/false);
  return s.is_object() && s.value("status", "") == "completed" ? s : json(nullptr);
}

// Runs one point as `fibrodem run` in a process of its own: its manifest goes
// to dir/manifest.json, its summary.json comes back (or is kept from before).
void run_point(const SweepFile& sweep, SweepRun& point, const std::filesystem::path& dir, bool overwrite,
               bool no_report) {
  try {
    const json manifest = point_manifest(sweep, point.values);
    parse_scene(manifest);  // a bad point is named here, before a process is spent on it
    const std::string manifest_text = manifest.dump(2, ' ', false, json::error_handler_t::replace);
    if (!overwrite)
      if (json before = completed_before(dir, manifest_text); !before.is_null()) {
        point.summary = std::move(before);
        point.status = "completed";
        point.reused = true;
        return;
      }
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / "manifest.json";
    std::ofstream(file) << manifest_text;
    const std::string self = boost::dll::program_location().string();
    // (The folder is the sweep's own: an earlier run of another manifest there is replaced.)
    std::vector<std::string> args = {self, "run", file.string(), "--quiet", "--out", dir.string(),
                                     "--set", "solver.threads=1", "--overwrite"};
    if (no_report) args.push_back("--no-report");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;  // its console quiet: its run.log says it all
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (dir / "stderr.txt").c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) throw std::runtime_error("cannot start " + self + ": " + std::strerror(spawned));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (std::filesystem::exists(dir / "summary.json"))
      point.summary = json::parse(std::ifstream(dir / "summary.json"));
    if (WIFSIGNALED(status)) {
      point.status = "crashed";
      point.error = "the run's process died of signal " + std::to_string(WTERMSIG(status)) + " (" +
                    strsignal(WTERMSIG(status)) + "); see " + (dir / "run.log").string();
      return;
    }
    point.status = point.summary.is_object() ? point.summary.value("status", "failed") : "failed";
    if (point.status != "completed")
      point.error = point.summary.is_object() ? point.summary.value("error", std::string("exit status ") +
                                                                                std::to_string(WEXITSTATUS(status)))
                                              : last_line(dir / "stderr.txt", "exit status " + std::to_string(WEXITSTATUS(status)));
  } catch (const std::exception& e) {
    point.status = "failed";
    point.error = e.what();
  }
}

// A run's outcome as text for gathering to rank 0, and back.
json outcome_json(std::size_t k, const SweepRun& r) {
  return {{"run", k}, {"summary", r.summary}, {"status", r.status}, {"error", r.error}, {"reused", r.reused}};
}

void take_outcome(const json& j, std::vector<SweepRun>& runs) {
  SweepRun& r = runs.at(j.at("run").get<std::size_t>());
  r.summary = j.at("summary");
  r.status = j.at("status").get<std::string>();
  r.error = j.at("error").get<std::string>();
  r.reused = j.at("reused").get<bool>();
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  return guarded([&] {
    const MpiRanks ranks;
    const SweepFile sweep = read_sweep(
        read_manifest_file(args.sweep),
        [&](const std::string& manifest) {
          return read_manifest_file((std::filesystem::path(args.sweep).parent_path() / manifest).string());
        },
        args.overrides);
    std::vector<SweepRun> runs;
    for (const auto& values : sweep.points) runs.push_back({values, nullptr, "", "", false});
    const std::filesystem::path dir =
        args.out.empty() ? "out/sweep_" + sweep.base.value("name", std::string("scene")) : args.out;
    // This rank's runs (all of them without MPI), over a pool of workers
    // sharing this machine's cores with the other ranks here.
    std::vector<std::size_t> mine;
    for (std::size_t k = static_cast<std::size_t>(ranks.rank()); k < runs.size(); k += static_cast<std::size_t>(ranks.size()))
      mine.push_back(k);
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const unsigned jobs = args.jobs > 0 ? args.jobs : std::max(1u, cores / static_cast<unsigned>(ranks.on_this_host()));
    std::atomic<std::size_t> next{0};
    std::mutex print;
    std::vector<std::thread> workers;
    for (unsigned w = 0; w < jobs; ++w)
      workers.emplace_back([&] {
        for (std::size_t i; (i = next++) < mine.size();) {
          const std::size_t k = mine[i];
          run_point(sweep, runs[k], dir / ("run_" + std::to_string(k)), args.overwrite, args.no_report);
          std::lock_guard<std::mutex> lock(print);
          std::cerr << "run " << k + 1 << "/" << runs.size()
                    << (runs[k].reused ? " done before (same manifest): kept"
                        : runs[k].status == "completed" ? " done"
                                                        : " " + runs[k].status + ": " + runs[k].error)
                    << "\n";
        }
      });
    for (auto& t : workers) t.join();

    // Under MPI, rank 0 gathers the other ranks' outcomes and tabulates.
    if (ranks.launched()) {
      json outcomes = json::array();
      for (std::size_t k : mine) outcomes.push_back(outcome_json(k, runs[k]));
      const auto gathered = ranks.gather(outcomes.dump(-1, ' ', false, json::error_handler_t::replace));
      if (ranks.rank() != 0) return 0;
      for (const auto& text : gathered)
        for (const auto& j : json::parse(text)) take_outcome(j, runs);
    }
    std::size_t reused = 0;
    for (const auto& r : runs) reused += r.reused;
    const std::string md = write_sweep_tables(sweep, runs, dir, !args.no_report);
    std::cout << md << "\n";
    if (reused > 0)
      std::cout << reused << " of " << runs.size() << " runs completed before with the same manifest: kept, not run again\n";
    if (ranks.launched()) std::cout << "over " << ranks.size() << " MPI ranks\n";
    std::cout << "outputs: " << dir.string() << "/{sweep.csv,sweep.md," << (sweep.seeds.empty() ? "" : "sweep_stats.csv,")
              << "sweep.png," << (args.no_report ? "" : "report.html,") << "run_*/}\n";
    for (const auto& r : runs)
      if (r.status != "completed") return 4;
    return 0;
  });
}

}  // namespace fibrodem::cli
