#include "study/sweep_table.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "io/csv_writer.hpp"
#include "io/plot_png.hpp"
#include "report/sweep_report.hpp"
#include "measure/sample_statistics.hpp"
#include "measure/summary_metrics.hpp"

namespace fibrodem {

namespace {

std::string cell_text(const json& v) {
  if (v.is_number_float()) return format_number(v.get<double>());
  return v.is_string() ? v.get<std::string>() : v.dump(-1, ' ', false, json::error_handler_t::replace);
}

// A markdown cell: numbers to two decimals (below 0.005 in magnitude, two
// significant digits, so that 5e-17 does not read as 5.00); text as it is.
std::string shown(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x)) return text;
  if (x == std::floor(x) && std::abs(x) < 1e15) return text;  // whole numbers as written
  return std::abs(x) >= 0.005 ? fmt::format("{:.2f}", x) : fmt::format("{:.2g}", x);
}

void markdown_row(std::ostringstream& md, const std::vector<std::string>& cells) {
  for (const auto& c : cells) md << "| " << c << " ";
  md << "|\n";
}

std::vector<std::string> shown(const std::vector<std::string>& cells) {
  std::vector<std::string> out;
  for (const auto& c : cells) out.push_back(shown(c));
  return out;
}

void markdown_header(std::ostringstream& md, const std::vector<std::string>& header) {
  markdown_row(md, header);
  for (std::size_t i = 0; i < header.size(); ++i) md << "|---";
  md << "|\n";
}

// The runs of each grid point (consecutive: seeds vary fastest).
struct GridPoint {
  SweepValues values;  // without the seed
  std::vector<const SweepRun*> runs;
};

std::vector<GridPoint> grid_points(const SweepFile& sweep, const std::vector<SweepRun>& runs) {
  std::vector<GridPoint> points;
  const std::size_t per_point = sweep.seeds.empty() ? 1 : sweep.seeds.size();
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (k % per_point == 0) {
      GridPoint p;
      p.values = runs[k].values;
      if (!sweep.seeds.empty()) p.values.pop_back();  // the seed
      points.push_back(p);
    }
    points.back().runs.push_back(&runs[k]);
  }
  return points;
}

// Per grid point and metric, the statistics over its completed runs.
std::vector<std::vector<SampleSummary>> statistics(const std::vector<GridPoint>& points,
                                                   const std::vector<SummaryMetric>& list) {
  std::vector<std::vector<SampleSummary>> stats;
  for (const auto& p : points) {
    stats.emplace_back();
    for (const auto& m : list) {
      std::vector<double> values;
      for (const SweepRun* r : p.runs)
        if (r->status == "completed") values.push_back(m.of(r->summary));
      stats.back().push_back(m.proportion ? summarize_proportion(values) : summarize(values));
    }
  }
  return stats;
}

void write_statistics(const std::vector<GridPoint>& points, const std::vector<SummaryMetric>& list,
                      const std::vector<std::vector<SampleSummary>>& stats, const std::filesystem::path& dir,
                      std::ostringstream& md, ReportTable& table) {
  std::vector<std::string> header;
  for (const auto& [path, v] : points.front().values) header.push_back(path);
  header.push_back("seeds_completed");
  std::vector<std::string> csv_header = header;
  for (const auto& m : list)
    for (const char* s : {"_mean", "_sd", "_ci95_low", "_ci95_high"}) csv_header.push_back(m.name + s);
  CsvWriter csv(dir / "sweep_stats.csv", csv_header);
  md << "\nOver the seeds: mean [95 % confidence interval] (Student's t; for reentry_detected, the fraction\n"
        "of runs with re-entry [Wilson score interval]):\n\n";
  std::vector<std::string> md_header = header;
  for (const auto& m : list) md_header.push_back(m.name);
  markdown_header(md, md_header);
  table.header = md_header;
  for (std::size_t k = 0; k < points.size(); ++k) {
    std::vector<std::string> row;
    for (const auto& [path, v] : points[k].values) row.push_back(cell_text(v));
    std::size_t completed = 0;
    for (const SweepRun* r : points[k].runs) completed += r->status == "completed";
    row.push_back(std::to_string(completed));
    for (const auto& c : row) csv.cell(c);
    std::vector<std::string> md_row = shown(row);
    for (const auto& s : stats[k]) {
      for (double v : {s.mean, s.sd, s.ci95_low, s.ci95_high}) csv.cell(format_number_or_empty(v));
      md_row.push_back(!std::isfinite(s.mean) ? ""
                       : std::isfinite(s.ci95_low)
                           ? shown(format_number(s.mean)) + " [" + shown(format_number(s.ci95_low)) + ", " +
                                 shown(format_number(s.ci95_high)) + "]"
                           : format_number(s.mean));
    }
    csv.end_row();
    markdown_row(md, md_row);
    table.rows.push_back(md_row);
  }
}

// One panel per metric with a value, against the first grid axis; one
// series per combination of the other axes; 95 % CI bars (sweep.png, and
// the report's plot).
std::vector<PlotPanel> sweep_panels(const std::vector<GridPoint>& points, const std::vector<SummaryMetric>& list,
                                    const std::vector<std::vector<SampleSummary>>& stats) {
  const bool has_axis = !points.front().values.empty();
  const std::string axis = has_axis ? points.front().values.front().first : "grid point";
  std::vector<PlotPanel> panels;
  for (std::size_t m = 0; m < list.size(); ++m) {
    PlotPanel panel{list[m].name, axis, list[m].name, false, false, {}, {}};
    std::map<std::string, std::size_t> series_of;
    bool any = false;
    for (std::size_t k = 0; k < points.size(); ++k) {
      std::string label;
      for (std::size_t i = 1; i < points[k].values.size(); ++i)
        label += (label.empty() ? "" : ", ") + points[k].values[i].first + " = " + cell_text(points[k].values[i].second);
      if (!series_of.count(label)) {
        series_of[label] = panel.series.size();
        panel.series.push_back({label.empty() ? list[m].name : label, {}, {}, {}, {}});
      }
      PlotSeries& s = panel.series[series_of[label]];
      const json& x = has_axis ? points[k].values.front().second : json(k);
      s.x.push_back(x.is_number() ? x.get<double>() : static_cast<double>(s.x.size()));
      s.y.push_back(stats[k][m].mean);
      s.y_low.push_back(stats[k][m].ci95_low);
      s.y_high.push_back(stats[k][m].ci95_high);
      any |= std::isfinite(stats[k][m].mean) && (list[m].drawn_when_zero || stats[k][m].mean != 0);
    }
    if (any) panels.push_back(std::move(panel));
  }
  return panels;
}

constexpr const char* kPlotTitle = "sweep: mean over the seeds, bars 95 % confidence interval";

void write_plot(const std::vector<PlotPanel>& panels, const std::filesystem::path& dir) {
  if (panels.empty()) return;
  const std::size_t columns = std::min<std::size_t>(4, panels.size()), rows = (panels.size() + columns - 1) / columns;
  write_plot_png(panels, dir / "sweep.png",
                 {.width_px = 400 * static_cast<int>(columns), .height_px = 30 + 360 * static_cast<int>(rows),
                  .font_px = 13, .title = kPlotTitle, .columns = columns});
}

}  // namespace

std::vector<GridPointStatistics> grid_point_statistics(const SweepFile& sweep, const std::vector<SweepRun>& runs) {
  const std::vector<GridPoint> points = grid_points(sweep, runs);
  const auto stats = statistics(points, summary_metrics());
  std::vector<GridPointStatistics> out;
  for (std::size_t k = 0; k < points.size(); ++k) {
    GridPointStatistics p{points[k].values, 0, stats[k]};
    for (const SweepRun* r : points[k].runs) p.completed += r->status == "completed";
    out.push_back(std::move(p));
  }
  return out;
}

std::string write_sweep_tables(const SweepFile& sweep, const std::vector<SweepRun>& runs,
                               const std::filesystem::path& dir, bool report) {
  SweepReportContent content;
  const std::vector<SummaryMetric>& list = summary_metrics();
  std::vector<std::string> header = {"run"};
  for (const auto& [path, v] : runs.front().values) header.push_back(path);
  for (const auto& m : list) header.push_back(m.name);
  header.push_back("status");
  CsvWriter csv(dir / "sweep.csv", header);
  std::ostringstream md;
  markdown_header(md, header);
  content.runs.header = header;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    std::vector<std::string> row = {std::to_string(k)};
    for (const auto& [path, v] : runs[k].values) row.push_back(cell_text(v));
    for (const auto& m : list) row.push_back(format_number_or_empty(m.of(runs[k].summary)));
    row.push_back(runs[k].status);
    for (const auto& c : row) csv.cell(c);
    csv.end_row();
    markdown_row(md, shown(row));
    content.runs.rows.push_back(shown(row));
    content.run_dirs.push_back("run_" + std::to_string(k));
  }
  const std::vector<GridPoint> points = grid_points(sweep, runs);
  const auto stats = statistics(points, list);
  if (!sweep.seeds.empty()) write_statistics(points, list, stats, dir, md, content.statistics);
  bool any_failed = false;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (runs[k].status != "completed") {
      if (!any_failed) md << "\nRuns that did not complete:\n\n";
      any_failed = true;
      md << "- run " << k << ", " << runs[k].status << ": " << runs[k].error << "\n";
      content.failures.push_back("run " + std::to_string(k) + ", " + runs[k].status + ": " + runs[k].error);
    }
  content.panels = sweep_panels(points, list, stats);
  write_plot(content.panels, dir);
  std::ofstream(dir / "sweep.md") << md.str();
  if (report) {
    const auto name = dir.filename().empty() ? dir.parent_path().filename() : dir.filename();  // "out/" too
    content.title = "fibrodem sweep: " + name.string();
    content.plot_title = kPlotTitle;
    write_sweep_report(dir, content);
  }
  return md.str();
}

}  // namespace fibrodem
