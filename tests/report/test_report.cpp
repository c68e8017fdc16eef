// report.html's pieces without a browser: the page writer, SVG plots, CSV
// read-back of a killed run's files, trace thinning, biomarker spread, the
// report written (or not) at the end of a run, and output.report's checks.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "io/csv_table.hpp"
#include "io/plot_svg.hpp"
#include "report/biomarker_spread.hpp"
#include "report/html_document.hpp"
#include "report/trace_panels.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_CASE("report pieces: HTML escaping and base64 as RFC 4648 gives them") {
  CHECK(html_escape("<a href=\"x\">R&D's</a>") == "&lt;a href=&quot;x&quot;&gt;R&amp;D&#39;s&lt;/a&gt;");
  // RFC 4648 section 10 test vectors.
  CHECK(base64("") == "");
  CHECK(base64("f") == "Zg==");
  CHECK(base64("fo") == "Zm8=");
  CHECK(base64("foo") == "Zm9v");
  CHECK(base64("foobar") == "Zm9vYmFy");
  // Bytes above 0x7f and a zero byte (a PNG's): Python's base64.b64encode(bytes([255, 254, 0, 128])).
  CHECK(base64(std::string("\xff\xfe\x00\x80", 4)) == "//4AgA==");
}

TEST_CASE("report pieces: SVG plots get ids unique in the page and scale to its width") {
  PlotPanel panel{"V", "t [ms]", "V", false, false, {{"cell 0", {0, 1, 2}, {-80, 20, -70}}}, {}};
  const std::string a = plot_svg({panel}, {.width_px = 600, .height_px = 300, .font_px = 15, .title = "", .columns = 1}, "pa-");
  const std::string b = plot_svg({panel}, {.width_px = 600, .height_px = 300, .font_px = 15, .title = "", .columns = 1}, "pb-");
  CHECK(a.rfind("<svg ", 0) == 0);
  CHECK(a.find("viewBox=\"0 0 600 300\"") != std::string::npos);
  CHECK(a.find("width:100%") != std::string::npos);
  // Every id Cairo wrote carries the prefix, and every reference too.
  for (const auto& [svg, prefix] : {std::pair{a, std::string("pa-")}, std::pair{b, std::string("pb-")}}) {
    std::size_t ids = 0;
    for (std::size_t at = svg.find(" id=\""); at != std::string::npos; at = svg.find(" id=\"", at + 1), ++ids)
      CHECK(svg.compare(at + 5, prefix.size(), prefix) == 0);
    CHECK(ids > 0);  // glyphs at least (the title, tick labels)
    for (std::size_t at = svg.find("href=\"#"); at != std::string::npos; at = svg.find("href=\"#", at + 1))
      CHECK(svg.compare(at + 7, prefix.size(), prefix) == 0);
  }
}

TEST_CASE("report pieces: a CSV cut short by a kill is read up to its last whole row") {
  const auto dir = testing::scratch_dir("report_csv");
  std::ofstream(dir / "t.csv") << "t_ms,V_0,eps_xx\n0,-80,0\n0.5,-79.5,0.001\n1,-7";  // last row cut
  const auto table = read_csv_table(dir / "t.csv");
  REQUIRE(table);
  CHECK(table->header == std::vector<std::string>{"t_ms", "V_0", "eps_xx"});
  CHECK(table->rows.size() == 2);
  CHECK(table->skipped_rows == 1);
  CHECK(table->numbers(1)[1] == -79.5);
  CHECK(!read_csv_table(dir / "missing.csv"));
  CHECK(parse_trace_heading("Ca_i_12").variable == "Ca_i");
  CHECK(parse_trace_heading("Ca_i_12").cell == 12);
  CHECK(parse_trace_heading("eps_xx").cell == -1);
  CHECK(parse_trace_heading("dt_ms").variable == "dt_ms");
}

TEST_CASE("report pieces: thinning keeps each bucket's extremes, in time order") {
  // An upstroke one sample wide in 10000: the thinned line still reaches it.
  std::vector<double> t, y;
  for (int i = 0; i < 10000; ++i) {
    t.push_back(i * 0.1);
    y.push_back(i == 4321 ? 40.0 : -80.0 + 1e-4 * i);
  }
  std::vector<double> t_out, y_out;
  thin_min_max(t, y, 1000, t_out, y_out);
  CHECK(t_out.size() <= 1000);
  CHECK(*std::max_element(y_out.begin(), y_out.end()) == 40.0);
  CHECK(*std::min_element(y_out.begin(), y_out.end()) == -80.0);
  CHECK(std::is_sorted(t_out.begin(), t_out.end()));
  thin_min_max({0, 1}, {5, 6}, 1000, t_out, y_out);  // short: as it is
  CHECK(y_out == std::vector<double>{5, 6});
}

TEST_CASE("report pieces: a trace panel's y axis names the variable's unit where it is known") {
  CsvTable traces;
  traces.header = {"t_ms", "V_0", "V_1", "Ca_i_0", "eps_xx"};
  traces.rows = {{"0", "-80", "-50", "0.0001", "0"}, {"1", "-79", "-50", "0.0002", "0.01"}};
  const auto panels = trace_panels(traces, {}, {{"V", "mV"}, {"Ca_i", "mM"}, {"eps_xx", "1"}});
  REQUIRE(panels.size() == 3);
  CHECK(panels[0].y_label == "V [mV]");
  CHECK(panels[0].series.size() == 2);
  CHECK(panels[1].y_label == "Ca_i [mM]");
  CHECK(panels[2].y_label == "eps_xx [1]");
  CHECK(trace_panels(traces, {})[0].y_label == "V");  // no unit known: the name alone
}

TEST_CASE("report pieces: biomarker spread per type, checked against values by hand") {
  CsvTable table;
  table.header = {"cell", "type", "beat", "apd90_ms", "rmp_mV"};
  table.rows = {{"0", "myocyte", "0", "200", "-80"}, {"0", "myocyte", "1", "220", "-78"},
                {"1", "fibroblast", "0", "", "-50"}};
  // The digest fed the rows in memory, in its two passes.
  BiomarkerDigest digest(table.header, {1});
  for (const auto& row : table.rows) digest.first_pass(row);
  for (const auto& row : table.rows) digest.second_pass(row);
  const auto spread = digest.spread();
  REQUIRE(spread.size() == 4);  // 2 types x 2 columns present
  CHECK(spread[0].type == "myocyte");
  CHECK(spread[0].metric == "apd90_ms");
  CHECK(spread[0].n == 2);
  CHECK(spread[0].mean == doctest::Approx(210));
  CHECK(spread[0].sd == doctest::Approx(std::sqrt(200.0)));  // (10^2 + 10^2) / (2 - 1)
  CHECK(spread[0].min == 200);
  CHECK(spread[0].max == 220);
  CHECK(spread[2].n == 0);  // a fibroblast has no APD here
  CHECK(std::isnan(spread[2].mean));
  // Histograms: one per type and biomarker with values; counts add up to n.
  const auto panels = digest.histograms();
  REQUIRE(panels.size() == 3);
  double counted = 0;
  for (std::size_t i = 1; i + 1 < panels[0].series[0].y.size(); i += 2) counted += panels[0].series[0].y[i];
  CHECK(counted == 2);
  CHECK(digest.types().at(1) == "fibroblast");
}

TEST_CASE("report pieces: biomarkers.csv read row by row gives the by-hand spread of its whole rows") {
  const auto dir = testing::scratch_dir("report_biomarkers_stream");
  // The rows of the test above, then a row cut by a kill (not counted).
  std::ofstream(dir / "biomarkers.csv") << "cell,type,beat,apd90_ms,rmp_mV\n0,myocyte,0,200,-80\n"
                                           "0,myocyte,1,220,-78\n1,fibroblast,0,,-50\n2,myocyte,0,9";
  const auto digest = digest_biomarkers_csv(dir / "biomarkers.csv", {1});
  REQUIRE(digest);
  CHECK(digest->rows() == 3);
  const auto spread = digest->spread();
  REQUIRE(spread.size() == 4);
  CHECK(spread[0].type == "myocyte");
  CHECK(spread[0].n == 2);
  CHECK(spread[0].mean == doctest::Approx(210));
  CHECK(spread[0].sd == doctest::Approx(std::sqrt(200.0)));  // (10^2 + 10^2) / (2 - 1)
  CHECK(spread[0].min == 200);
  CHECK(spread[0].max == 220);
  CHECK(spread[1].mean == doctest::Approx(-79));  // rmp: (-80 - 78) / 2
  CHECK(spread[2].n == 0);
  CHECK(std::isnan(spread[2].mean));
  CHECK(spread[3].n == 1);
  CHECK(spread[3].mean == -50);
  CHECK(std::isnan(spread[3].sd));  // one value: no SD
  // Histograms: counts add up to n; one value gets one bin of width 1 around it.
  const auto panels = digest->histograms();
  REQUIRE(panels.size() == 3);
  double counted = 0;
  for (std::size_t i = 1; i + 1 < panels[0].series[0].y.size(); i += 2) counted += panels[0].series[0].y[i];
  CHECK(counted == 2);
  CHECK(panels[2].series[0].x.front() == -50.5);
  CHECK(panels[2].series[0].x.back() == -49.5);
  // Only the cells asked for are typed (the traced cells, in the report).
  CHECK(digest->types() == std::map<int, std::string>{{1, "fibroblast"}});
  CHECK(!digest_biomarkers_csv(dir / "missing.csv", {}));
}

TEST_CASE("report pieces: the page written to a file is the page as text") {
  const auto dir = testing::scratch_dir("report_write");
  HtmlDocument page("a <title>");
  page.heading(2, "Scene", "scene");
  page.table({"a", "b"}, {{"1", "x"}});
  page.png_animation("frames", {{"t = 0", "PNG"}});  // a slider: the page carries its script
  page.write(dir / "page.html");
  CHECK(testing::read_file(dir / "page.html") == page.str());
  CHECK(page.str().find("<title>a &lt;title&gt;</title>") != std::string::npos);
  CHECK(page.str().find("function fibrodemShowFrame") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "page.html.tmp"));
}

TEST_CASE("a run writes report.html with its cost in summary.json, and output.report false writes none") {
  const auto dir = testing::scratch_dir("report_run");
  json m = testing::passive_cell_manifest();
  Scene scene = parse_scene(m);
  scene.output.dir = (dir / "on").string();
  Simulation(scene).run();
  const std::string page = testing::read_file(dir / "on" / "report.html");
  CHECK(page.find("<title>fibrodem run: passive_cell</title>") != std::string::npos);
  CHECK(page.find("completed: 100") != std::string::npos);
  CHECK(page.find("<svg ") != std::string::npos);  // the V trace
  // Every parameter value used, from summary.json's models (the plugin's defaults here).
  CHECK(page.find("parameters used: fibroblast (passive_fibroblast") != std::string::npos);
  CHECK(page.find("R_GOhm = 10.7") != std::string::npos);
  const json summary = json::parse(testing::read_file(dir / "on" / "summary.json"));
  CHECK(summary["report_time_s"].get<double>() > 0);
  // The V axis carries the unit the plugin declares for its state V
  // (passive_fibroblast: mV), through summary.json's trace_units.
  CHECK(summary["trace_units"]["V"] == "mV");
  CHECK(testing::read_file(dir / "on" / "run.log").find("report.html written in") != std::string::npos);

  m["output"]["report"] = false;
  Scene off = parse_scene(m);
  off.output.dir = (dir / "off").string();
  Simulation(off).run();
  CHECK(!std::filesystem::exists(dir / "off" / "report.html"));
  CHECK(!json::parse(testing::read_file(dir / "off" / "summary.json")).contains("report_time_s"));

  m["output"]["report"] = "no";
  try {
    parse_scene(m);
    FAIL("output.report \"no\" was accepted");
  } catch (const ManifestError& e) {
    CHECK(e.path() == "output.report");
  }
}
