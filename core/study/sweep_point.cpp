#include "study/sweep_point.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "run/simulation.hpp"
#include "study/plugin_search.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

// Single-threaded, so that a point's numbers are those of a lone run (and
// the sweep's workers, not the runs, share the cores).
constexpr const char* kOneThread = "solver.threads=1";

// The last line a run printed to its standard error (its error, when it
// stopped before writing a summary), else `otherwise`.
std::string last_line(const fs::path& file, const std::string& otherwise) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last.empty() ? otherwise : last;
}

// The summary of a completed run of exactly this manifest in dir, if there is one.
json completed_before(const fs::path& dir, const std::string& manifest_text) {
  std::ifstream manifest(dir / "manifest.json"), summary(dir / "summary.json");
  if (!manifest || !summary) return nullptr;
  std::ostringstream text;
  text << manifest.rdbuf();
  if (text.str() != manifest_text) return nullptr;
  const json s = json::parse(summary, nullptr, /*allow_exceptions=*/false);
  return s.is_object() && s.value("status", "") == "completed" ? s : json(nullptr);
}

json summary_in(const fs::path& dir) {
  if (!fs::exists(dir / "summary.json")) return nullptr;
  return json::parse(std::ifstream(dir / "summary.json"), nullptr, /*allow_exceptions=*/false);
}

// `EXE run` in a process of its own, its console quiet (its run.log says it
// all; its standard error goes to dir/stderr.txt).
void run_in_child(const fs::path& executable, SweepRun& point, const fs::path& dir, bool report) {
  const std::string self = executable.string();
  const fs::path file = dir / "manifest.json";
  // (The folder is the sweep's own: an earlier run of another manifest there is replaced.)
  std::vector<std::string> args = {self, "run", file.string(), "--quiet", "--out", dir.string(),
                                   "--set", kOneThread, "--overwrite"};
  if (!report) args.push_back("--no-report");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
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
  point.summary = summary_in(dir);
  if (WIFSIGNALED(status)) {
    point.status = "crashed";
    point.error = "the run's process died of signal " + std::to_string(WTERMSIG(status)) + " (" +
                  strsignal(WTERMSIG(status)) + "); see " + (dir / "run.log").string();
    return;
  }
  const std::string exit_status = "exit status " + std::to_string(WEXITSTATUS(status));
  point.status = point.summary.is_object() ? point.summary.value("status", "failed") : "failed";
  if (point.status != "completed")
    point.error = point.summary.is_object() ? point.summary.value("error", exit_status)
                                            : last_line(dir / "stderr.txt", exit_status);
}

// One Simulation here, as `fibrodem run --set solver.threads=1 --overwrite` runs it.
void run_here(const InProcessRunner& runner, const json& manifest, SweepRun& point, const fs::path& dir,
              bool report) {
  json single = manifest;
  apply_override(single, kOneThread);
  Scene scene = parse_scene(single);
  scene.output.dir = dir.string();
  scene.output.overwrite = true;
  if (!report) scene.output.report = false;
  std::string error;
  try {
    Simulation simulation(scene, registry_searching(scene, runner.plugin_search_path));
    simulation.run();
  } catch (const std::exception& e) {
    error = e.what();
  }
  point.summary = summary_in(dir);
  point.status = point.summary.is_object() ? point.summary.value("status", "failed") : "failed";
  if (point.status != "completed")
    point.error = point.summary.is_object() ? point.summary.value("error", error) : error;
}

}  // namespace

void run_sweep_point(const SweepFile& sweep, SweepRun& point, const fs::path& dir, const PointRunner& runner,
                     bool overwrite, bool report) {
  try {
    const json manifest = point_manifest(sweep, point.values);
    parse_scene(manifest);  // a bad point is named here, before a run is spent on it
    const std::string manifest_text = manifest.dump(2, ' ', false, json::error_handler_t::replace);
    if (!overwrite)
      if (json before = completed_before(dir, manifest_text); !before.is_null()) {
        point.summary = std::move(before);
        point.status = "completed";
        point.reused = true;
        return;
      }
    fs::create_directories(dir);
    std::ofstream(dir / "manifest.json") << manifest_text;
    if (const auto* child = std::get_if<ChildProcessRunner>(&runner))
      run_in_child(child->executable, point, dir, report);
    else
      run_here(std::get<InProcessRunner>(runner), manifest, point, dir, report);
  } catch (const std::exception& e) {
    point.status = "failed";
    point.error = e.what();
  }
}

}  // namespace fibrodem
