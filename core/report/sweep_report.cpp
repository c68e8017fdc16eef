#include "report/sweep_report.hpp"

#include <algorithm>

#include "io/plot_svg.hpp"
#include "report/html_document.hpp"

namespace fibrodem {

std::filesystem::path write_sweep_report(const std::filesystem::path& dir, const SweepReportContent& content) {
  HtmlDocument page(content.title);
  if (!content.failures.empty())
    page.notice("error", std::to_string(content.failures.size()) + " run(s) did not complete", content.failures);
  else
    page.notice("ok", "all " + std::to_string(content.runs.rows.size()) + " runs completed", {});
  if (!content.panels.empty()) {
    const std::size_t columns = std::min<std::size_t>(3, content.panels.size());
    const std::size_t rows = (content.panels.size() + columns - 1) / columns;
    page.svg_figure(content.plot_title,
                    plot_svg(content.panels,
                             {.width_px = 1200, .height_px = 340 * static_cast<int>(rows), .font_px = 14,
                              .title = "", .columns = columns},
                             "sweep-"));
  }
  if (!content.statistics.rows.empty()) {
    page.heading(2, "Over the seeds", "statistics");
    page.paragraph("Per grid point: each metric's mean [95 % confidence interval] over the seeds (Student's t).");
    page.table(content.statistics.header, content.statistics.rows);
  }
  page.heading(2, "Runs", "runs");
  page.table(content.runs.header, content.runs.rows);
  std::string links = "<p>Each run's own report: ";
  for (std::size_t k = 0; k < content.run_dirs.size(); ++k)
    links += (k ? ", " : "") + std::string("<a href=\"") + html_escape(content.run_dirs[k]) + "/report.html\">" +
             html_escape(content.run_dirs[k]) + "</a>";
  page.raw(links + "</p>\n");
  const auto file = dir / "report.html";
  page.write(file);
  return file;
}

}  // namespace fibrodem
