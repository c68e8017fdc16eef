// `fibrodem sweep SWEEP.json [--out DIR] [--jobs N]`: runs a manifest over the
// Cartesian product of parameter values and tabulates the results.
//
//   { "fibrodem_sweep": 1,
//     "manifest": "cell_pair_active.json",          (relative to the sweep file)
//     "set":  { "duration_ms": 5000 },              (optional, every run)
//     "grid": { "tissue.fibroblasts": [1, 2, 4],
//               "coupling.D_f_nS": [0.5, 1, 2, 4, 8] } }
//
// Runs go to DIR/run_<k>/; DIR/sweep.csv and DIR/sweep.md have one row per run:
// the grid values, per-cell-type mean biomarkers, CV, peak strain and status. Runs are
// spread over N worker threads (each run single-threaded, so the numbers are
// those of a lone run).
#include <atomic>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "apps/commands.hpp"
#include "io/csv_writer.hpp"
#include "run/simulation.hpp"

namespace fibrodem::cli {

namespace {

struct SweepPoint {
  std::vector<std::pair<std::string, json>> values;  // grid path -> value
  json summary;
  std::string error;
};

std::vector<SweepPoint> expand_grid(const json& grid) {
  std::vector<SweepPoint> points(1);
  for (const auto& [path, values] : grid.items()) {
    if (!values.is_array() || values.empty())
      throw ManifestError("grid." + path, "expected a non-empty list of values");
    std::vector<SweepPoint> next;
    for (const auto& point : points)
      for (const auto& v : values) {
        SweepPoint p = point;
        p.values.emplace_back(path, v);
        next.push_back(p);
      }
    points = std::move(next);
  }
  return points;
}

std::string assignment(const std::string& path, const json& value) { return path + "=" + value.dump(); }

void run_point(const json& base, SweepPoint& point, const std::filesystem::path& dir, bool overwrite) {
  try {
    json manifest = base;
    for (const auto& [path, value] : point.values) apply_override(manifest, assignment(path, value));
    Scene scene = parse_scene(manifest);
    scene.output.dir = dir.string();
    scene.output.overwrite = overwrite;
    scene.solver.threads = 1;
    Simulation simulation(scene);
    simulation.run();
    point.summary = simulation.summary();
  } catch (const std::exception& e) {
    point.error = e.what();
  }
}

std::string cell_text(const json& v) {
  if (v.is_number_float()) return format_number(v.get<double>());
  return v.is_string() ? v.get<std::string>() : v.dump();
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  return guarded([&] {
    const json sweep = read_manifest_file(args.sweep);
    JsonReader r(sweep, "");
    r.integer("fibrodem_sweep", std::nullopt, 1, 1);
    const std::filesystem::path manifest_file =
        std::filesystem::path(args.sweep).parent_path() / r.text("manifest", std::nullopt);
    json base = read_manifest_file(manifest_file.string());
    const json& fixed = r.raw("set");
    if (!fixed.is_null())
      for (const auto& [path, value] : fixed.items()) apply_override(base, assignment(path, value));
    const json& grid = r.raw("grid");
    if (!grid.is_object()) throw ManifestError("grid", "expected an object of dotted paths to lists of values");
    r.finish();

    std::vector<SweepPoint> points = expand_grid(grid);
    const std::filesystem::path dir = args.out.empty() ? "out/sweep_" + base.value("name", std::string("scene")) : args.out;
    const unsigned jobs = args.jobs > 0 ? args.jobs : std::max(1u, std::thread::hardware_concurrency());
    std::atomic<std::size_t> next{0};
    std::mutex print;
    std::vector<std::thread> workers;
    for (unsigned w = 0; w < jobs; ++w)
      workers.emplace_back([&] {
        for (std::size_t k; (k = next++) < points.size();) {
          run_point(base, points[k], dir / ("run_" + std::to_string(k)), args.overwrite);
          std::lock_guard<std::mutex> lock(print);
          std::cerr << "run " << k + 1 << "/" << points.size() << (points[k].error.empty() ? " done" : " FAILED: " + points[k].error) << "\n";
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
      row.push_back(points[k].error.empty() ? "completed" : "failed");
      for (const auto& c : row) {
        csv.cell(c);
        std::string shown = c;
        if (const auto dot = shown.find('.'); dot != std::string::npos && shown.size() > dot + 3) shown.resize(dot + 3);
        md << "| " << shown << " ";
      }
      csv.end_row();
      md << "|\n";
    }
    std::ofstream(dir / "sweep.md") << md.str();
    std::cout << md.str() << "\noutputs: " << dir.string() << "/{sweep.csv,sweep.md,run_*/}\n";
    for (const auto& p : points)
      if (!p.error.empty()) return 4;
    return 0;
  });
}

}  // namespace fibrodem::cli
