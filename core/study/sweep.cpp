#include "study/sweep.hpp"

#include <algorithm>
#include <stdexcept>

#include "scene/scene.hpp"
#include "study/worker_pool.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

SweepFile load_sweep_file(const fs::path& file, const std::vector<std::string>& overrides) {
  return read_sweep(
      read_manifest_file(file.string()),
      [&](const std::string& manifest) { return read_manifest_file((file.parent_path() / manifest).string()); },
      overrides);
}

fs::path default_sweep_dir(const SweepFile& sweep) {
  return "out/sweep_" + sweep.base.value("name", std::string("scene"));
}

std::vector<SweepRun> sweep_points(const SweepFile& sweep) {
  std::vector<SweepRun> runs;
  for (const auto& values : sweep.points) runs.push_back({values, nullptr, "", "", false});
  return runs;
}

void run_sweep_points(const SweepFile& sweep, std::vector<SweepRun>& runs, const std::vector<std::size_t>& which,
                      const SweepOptions& options) {
  if (options.out.empty()) throw std::invalid_argument("run_sweep_points: no output folder");
  if (const auto* child = std::get_if<ChildProcessRunner>(&options.runner); child && child->executable.empty())
    throw std::invalid_argument("run_sweep_points: a child-process runner without a fibrodem executable");
  for_each_in_parallel(
      which.size(), options.jobs,
      [&](std::size_t i) {
        const std::size_t k = which[i];
        if (options.stop_requested && options.stop_requested()) {
          runs[k].status = "interrupted";
          runs[k].error = "not run: the sweep was stopped";
        } else {
          run_sweep_point(sweep, runs[k], options.out / ("run_" + std::to_string(k)), options.runner,
                          options.overwrite, options.report);
        }
      },
      [&](std::size_t i) {
        if (options.on_point_done) options.on_point_done(which[i], runs[which[i]]);
      });
}

bool SweepResult::all_completed() const {
  return std::all_of(runs.begin(), runs.end(), [](const SweepRun& r) { return r.status == "completed"; });
}

SweepResult tabulate_sweep(const SweepFile& sweep, std::vector<SweepRun> runs, const SweepOptions& options) {
  SweepResult result;
  result.dir = options.out;
  result.markdown = write_sweep_tables(sweep, runs, options.out, options.report);
  result.statistics = grid_point_statistics(sweep, runs);
  for (const auto& r : runs) result.reused += r.reused;
  result.runs = std::move(runs);
  return result;
}

SweepResult run_sweep(const SweepFile& sweep, const SweepOptions& options) {
  std::vector<SweepRun> runs = sweep_points(sweep);
  std::vector<std::size_t> every(runs.size());
  for (std::size_t k = 0; k < every.size(); ++k) every[k] = k;
  run_sweep_points(sweep, runs, every, options);
  return tabulate_sweep(sweep, std::move(runs), options);
}

}  // namespace fibrodem
