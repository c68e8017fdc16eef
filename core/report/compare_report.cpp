#include "report/compare_report.hpp"

#include "compare/ab_comparison.hpp"
#include "io/csv_writer.hpp"
#include "io/plot_svg.hpp"
#include "report/html_document.hpp"
#include "report/trace_panels.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

void difference_table(HtmlDocument& page, const RunRecord& a, const RunRecord& b) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& r : compare_biomarkers(a, b))
    rows.push_back({r.type, r.metric, fixed_decimals(r.a, 2, "n/a"), fixed_decimals(r.b, 2, "n/a"),
                    fixed_decimals(r.diff(), 2, "n/a"), fixed_decimals(100 * r.relative_diff(), 1, "n/a")});
  page.heading(2, "Mean biomarkers", "biomarkers");
  page.table({"cell type", "biomarker", a.label, b.label, b.label + " - " + a.label, "relative [%]"}, rows);
}

void traces(HtmlDocument& page, const RunRecord& a, const RunRecord& b) {
  std::vector<PlotPanel> panels = comparison_trace_panels(a, b);
  page.heading(2, "Traces, " + a.label + " and " + b.label + " overlaid", "traces");
  if (panels.empty()) {
    page.paragraph("The two runs traced no column in common.");
    return;
  }
  for (std::size_t k = 0; k < panels.size(); ++k) {
    for (auto& s : panels[k].series) {  // a page of readable size (report/trace_panels)
      std::vector<double> t, y;
      thin_min_max(s.x, s.y, kMostPoints, t, y);
      s.x = std::move(t);
      s.y = std::move(y);
    }
    page.svg_figure(panels[k].title, plot_svg({panels[k]}, {.width_px = 1200, .height_px = 340, .font_px = 14,
                                                            .title = "", .columns = 1},
                                              "trace" + std::to_string(k) + "-"));
  }
}

void pictures(HtmlDocument& page, const fs::path& dir, const CompareReportInput& in) {
  for (const auto& [file, title] : {std::pair{"tissue.png", "Tissue by cell type"},
                                    std::pair{"activation_map.png", "Activation map (last beat)"}}) {
    if (!fs::exists(dir / in.a_dir / file) && !fs::exists(dir / in.b_dir / file)) continue;
    page.heading(2, title);
    page.begin_row();
    page.png_figure(in.a.label, dir / in.a_dir / file);
    page.png_figure(in.b.label, dir / in.b_dir / file);
    page.end_row();
  }
}

}  // namespace

fs::path write_compare_report(const fs::path& dir, const CompareReportInput& in) {
  HtmlDocument page("fibrodem compare: " + in.a.label + " and " + in.b.label);
  page.raw("<p>Each run's own report: <a href=\"" + html_escape((in.a_dir / "report.html").string()) + "\">" +
           html_escape(in.a.label) + "</a>, <a href=\"" + html_escape((in.b_dir / "report.html").string()) + "\">" +
           html_escape(in.b.label) + "</a>.</p>\n");
  difference_table(page, in.a, in.b);
  if (!in.paired_markdown.empty())
    page.details("Paired differences over the seeds (paired.md)", in.paired_markdown, true);
  traces(page, in.a, in.b);
  pictures(page, dir, in);
  const auto file = dir / "report.html";
  page.write(file);
  return file;
}

}  // namespace fibrodem
