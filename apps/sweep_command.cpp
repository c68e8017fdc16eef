// `fibrodem sweep SWEEP.json [--out DIR] [--jobs N]`: runs a manifest over the
// Cartesian product of parameter values and tabulates the results.
//
// (The sweep file: scene/sweep_file.hpp.)
// Runs go to DIR/run_<k>/; DIR/sweep.csv and DIR/sweep.md have one row per run:
// the grid values, per-cell-type mean biomarkers, CV, peak strain and status. Runs are
// spread over N workers, each point a `fibrodem run` process of its own
// (single-threaded, so the numbers are those of a lone run): a point that
// crashes (a segfault in a user's plugin) cannot take the others down; its
// status is "crashed" with the signal, or "failed" with its error.
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
#include "io/csv_writer.hpp"
#include "run/simulation.hpp"
#include "scene/sweep_file.hpp"

namespace fibrodem::cli {

namespace {

struct SweepPoint {
  SweepValues values;  // grid path -> value
  json summary;
  std::string status;  // completed | failed | interrupted | crashed
  std::string error;
};

// Runs one point as `fibrodem run` in a process of its own: its manifest goes
// to dir/manifest.json, its summary.json comes back.
void run_point(const SweepFile& sweep, SweepPoint& point, const std::filesystem::path& dir, bool overwrite) {
  try {
    const json manifest = point_manifest(sweep, point.values);
    parse_scene(manifest);  // a bad point is named here, before a process is spent on it
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / "manifest.json";
    std::ofstream(file) << manifest.dump(2, ' ', false, json::error_handler_t::replace);
    const std::string self = boost::dll::program_location().string();
    std::vector<std::string> args = {self, "run", file.string(), "--quiet", "--out", dir.string(),
                                     "--set", "solver.threads=1"};
    if (overwrite) args.push_back("--overwrite");
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
                                              : "exit status " + std::to_string(WEXITSTATUS(status));
  } catch (const std::exception& e) {
    point.status = "failed";
    point.error = e.what();
  }
}

std::string cell_text(const json& v) {
  if (v.is_number_float()) return format_number(v.get<double>());
  return v.is_string() ? v.get<std::string>() : v.dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  return guarded([&] {
    const SweepFile sweep = read_sweep(read_manifest_file(args.sweep), [&](const std::string& manifest) {
      return read_manifest_file((std::filesystem::path(args.sweep).parent_path() / manifest).string());
    });
    std::vector<SweepPoint> points;
    for (const auto& values : sweep.points) points.push_back({values, nullptr, "", ""});
    const std::filesystem::path dir =
        args.out.empty() ? "out/sweep_" + sweep.base.value("name", std::string("scene")) : args.out;
    const unsigned jobs = args.jobs > 0 ? args.jobs : std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::size_t> next{0};
    std::mutex print;
    std::vector<std::thread> workers;
    for (unsigned w = 0; w < jobs; ++w)
      workers.emplace_back([&] {
        for (std::size_t k; (k = next++) < points.size();) {
          run_point(sweep, points[k], dir / ("run_" + std::to_string(k)), args.overwrite);
          std::lock_guard<std::mutex> lock(print);
          std::cerr << "run " << k + 1 << "/" << points.size() << (points[k].status == "completed" ? " done" : " " + points[k].status + ": " + points[k].error) << "\n";
        }
      });
    for (auto& t : workers) t.join();

    // The table: grid values, then per-type means, CV and status.
    std::vector<std::string> header = {"run"};
    for (const auto& [path, v] : points.front().values) header.push_back(path);
    header.push_back("fm_ratio");
    const char* metrics[] = {"rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms"};
    for (const char* type : {"myocyte", "fibroblast"})
      for (const char* m : metrics) header.push_back(std::string(type) + "_" + m);
    header.insert(header.end(), {"cv_cm_per_s", "peak_eps_xx", "peak_eps_yy", "status"});
    CsvWriter csv(dir / "sweep.csv", header);
    std::ostringstream md;
    for (const auto& h : header) md << "| " << h << " ";
    md << "|\n";
    for (std::size_t i = 0; i < header.size(); ++i) md << "|---";
    md << "|\n";
    for (std::size_t k = 0; k < points.size(); ++k) {
      std::vector<std::string> row = {std::to_string(k)};
      for (const auto& [path, v] : points[k].values) row.push_back(cell_text(v));
      row.push_back(points[k].summary.is_null() || points[k].summary["fm_ratio"].is_null()
                        ? "" : cell_text(points[k].summary["fm_ratio"]));
      const json& means = points[k].summary.is_null() ? json::object() : points[k].summary["mean_biomarkers"];
      for (const char* type : {"myocyte", "fibroblast"})
        for (const char* m : metrics)
          row.push_back(means.contains(type) && !means[type][m].is_null() ? cell_text(means[type][m]) : "");
      row.push_back(points[k].summary.is_null() || points[k].summary["cv_cm_per_s"].is_null()
                        ? "" : cell_text(points[k].summary["cv_cm_per_s"]));
      for (const char* component : {"xx", "yy"})
        row.push_back(points[k].summary.is_null() || points[k].summary["peak_strain"].is_null()
                          ? "" : cell_text(points[k].summary["peak_strain"][component]));
      row.push_back(points[k].status);
      for (const auto& c : row) {
        csv.cell(c);
        std::string shown = c;
        if (const auto dot = shown.find('.'); dot != std::string::npos && shown.size() > dot + 3) shown.resize(dot + 3);
        md << "| " << shown << " ";
      }
      csv.end_row();
      md << "|\n";
    }
    bool any_failed = false;
    for (std::size_t k = 0; k < points.size(); ++k)
      if (points[k].status != "completed") {
        if (!any_failed) md << "\nPoints that did not complete:\n\n";
        any_failed = true;
        md << "- run " << k << ", " << points[k].status << ": " << points[k].error << "\n";
      }
    std::ofstream(dir / "sweep.md") << md.str();
    std::cout << md.str() << "\noutputs: " << dir.string() << "/{sweep.csv,sweep.md,run_*/}\n";
    return any_failed ? 4 : 0;
  });
}

}  // namespace fibrodem::cli
