// report.html of a run, an interrupted run, a sweep and a comparison, opened
// in a real browser (headless Chromium): no JavaScript or resource error,
// every plot and picture drawn, titles present, a screenshot that is not
// blank. Skipped (ctest: SKIP_REGULAR_EXPRESSION) where Chromium is missing.
//
// How the page is probed: a copy of the report gets a small script at the
// top of <head> that records window errors (a capture-phase listener also
// sees images that fail to decode, which console hooks do not),
// console.error calls and unhandled rejections, and on `load` writes what
// it found as JSON into a <pre id="probe">; `chromium --dump-dom` prints the
// DOM after load. This needs no DevTools-protocol client, and the report
// itself carries no test code. Chromium's own console log (--enable-logging)
// is checked as well, for anything the hooks cannot see.
#include <doctest/doctest.h>
#include <png.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>

#include "support/scenes.hpp"
#include "report/snapshot_frames.hpp"

using namespace fibrodem;

// Every case here is labelled "browser" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("browser");

namespace {

const std::string kFibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem";

// Printed when skipped: ctest reports the test as skipped on this text.
constexpr const char* kSkipMessage =
    "SKIPPED: chromium is not installed (apt-get install chromium, or FIBRODEM_CHROMIUM=PATH)";

// FIBRODEM_CHROMIUM names another browser binary (or a missing one, to see
// the skip); else Debian's chromium.
std::string chromium() {
  std::vector<std::string> names = {"chromium", "chromium-browser"};
  if (const char* chosen = std::getenv("FIBRODEM_CHROMIUM")) names = {chosen};
  for (const auto& name : names)
    if (std::system(("command -v '" + name + "' > /dev/null 2>&1").c_str()) == 0) return name;
  return "";
}

constexpr const char* kProbe = R"(<script>
window.__probe_errors = [];
window.addEventListener('error', function (e) {
  __probe_errors.push('error: ' + (e.message || (e.target && e.target.tagName + ' failed to load')));
}, true);
window.addEventListener('unhandledrejection', function (e) { __probe_errors.push('rejection: ' + e.reason); });
(function () {
  var original = console.error;
  console.error = function () { __probe_errors.push('console.error: ' + [].join.call(arguments, ' ')); original.apply(console, arguments); };
})();
window.addEventListener('load', function () {
  var images = document.images, broken = 0;
  for (var i = 0; i < images.length; ++i) if (!(images[i].complete && images[i].naturalWidth > 0)) ++broken;
  var svgs = [].filter.call(document.querySelectorAll('svg'), function (s) { return !s.parentNode.closest('svg'); });
  var empty_svgs = svgs.filter(function (s) {
    var box = s.getBoundingClientRect();
    return box.width < 100 || box.height < 50 || s.querySelectorAll('path').length < 5;
  }).length;
  var captions = [].map.call(document.querySelectorAll('figcaption'), function (c) { return c.textContent; });
  var probe = document.createElement('pre');
  probe.id = 'probe';
  probe.textContent = JSON.stringify({errors: __probe_errors, svg: svgs.length, empty_svg: empty_svgs,
                                      img: images.length, broken_img: broken, captions: captions,
                                      title: document.title, h1: document.querySelector('h1').textContent});
  document.body.appendChild(probe);
});
</script>)";

struct BrowserView {
  json probe;
  std::string console;  // Chromium's log lines about the page's console
  double inked_fraction = 0;  // of the screenshot's pixels, not near-white
  std::size_t colours = 0;    // distinct colours in the screenshot (coarse)
};

std::string unescape_html(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""},
                                 {"&#39;", "'"}, {"&amp;", "&"}})
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

// Runs a shell command, returns its standard output.
std::string output_of(const std::string& command) {
  std::unique_ptr<FILE, decltype(&pclose)> pipe(popen(command.c_str(), "r"), pclose);
  std::string out;
  char buffer[65536];
  for (std::size_t n; pipe && (n = std::fread(buffer, 1, sizeof buffer, pipe.get())) > 0;) out.append(buffer, n);
  return out;
}

void read_screenshot(const std::filesystem::path& file, BrowserView& view) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  REQUIRE_MESSAGE(png_image_begin_read_from_file(&image, file.c_str()) != 0, "no screenshot at " << file);
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
  REQUIRE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) != 0);
  std::size_t inked = 0;
  std::set<int> colours;
  for (std::size_t p = 0; p + 2 < pixels.size(); p += 3) {
    const int r = pixels[p], g = pixels[p + 1], b = pixels[p + 2];
    inked += (r < 235 || g < 235 || b < 235);
    colours.insert((r >> 4) << 8 | (g >> 4) << 4 | (b >> 4));
  }
  view.inked_fraction = static_cast<double>(inked) / static_cast<double>(pixels.size() / 3);
  view.colours = colours.size();
}

// Opens a copy of `report` with the probe in headless Chromium: the DOM
// after load, and a 1280 x 1600 screenshot of its top.
BrowserView open_in_browser(const std::string& browser, const std::filesystem::path& report) {
  const auto dir = report.parent_path();
  std::string page = testing::read_file(report);
  const std::size_t head = page.find("<head>");
  REQUIRE_MESSAGE(head != std::string::npos, report << " has no <head>");
  page.insert(head + 6, kProbe);
  const auto probed = dir / "report.probed.html";
  std::ofstream(probed) << page;
  // Its own profile: tests run side by side (ctest -j). --no-sandbox: CI runs as root.
  const std::string flags = " --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" +
                            (dir / "chromium_profile").string() + " --enable-logging=stderr --v=0 ";
  const std::string url = "file://" + std::filesystem::absolute(probed).string();
  const std::string dom = output_of("timeout 120 " + browser + flags + "--virtual-time-budget=3000 --dump-dom " +
                                    url + " 2> " + (dir / "chromium_dom.log").string());
  const std::size_t open = dom.find("<pre id=\"probe\">"), close = dom.find("</pre>", open);
  REQUIRE_MESSAGE(open != std::string::npos, "the probe did not run; Chromium's log: "
                                                 << testing::read_file(dir / "chromium_dom.log"));
  BrowserView view;
  view.probe = json::parse(unescape_html(dom.substr(open + 16, close - open - 16)));
  std::istringstream log(testing::read_file(dir / "chromium_dom.log"));
  for (std::string line; std::getline(log, line);)
    if (line.find(":CONSOLE(") != std::string::npos) view.console += line + "\n";
  const auto shot = dir / "screenshot.png";
  std::filesystem::remove(shot);
  std::system(("timeout 120 " + browser + flags + "--window-size=1280,1600 --screenshot=" + shot.string() + " " + url +
               " > /dev/null 2>&1")
                  .c_str());
  read_screenshot(shot, view);
  return view;
}

// What every report must show in a browser.
void check_drawn(const BrowserView& view, std::size_t svgs, std::size_t images, const std::vector<std::string>& captions,
                 const std::string& title_start) {
  CAPTURE(view.probe.dump());
  CHECK(view.probe["errors"].empty());
  CHECK(view.console.empty());
  CHECK(view.probe["svg"] == svgs);
  CHECK(view.probe["empty_svg"] == 0);
  CHECK(view.probe["img"] == images);
  CHECK(view.probe["broken_img"] == 0);
  CHECK(view.probe["title"].get<std::string>().rfind(title_start, 0) == 0);
  CHECK(view.probe["h1"] == view.probe["title"]);
  const auto shown = view.probe["captions"].get<std::vector<std::string>>();
  for (const auto& caption : captions) {
    CAPTURE(caption);
    CHECK(std::find_if(shown.begin(), shown.end(), [&](const std::string& s) { return s.rfind(caption, 0) == 0; }) !=
          shown.end());
  }
  // Not blank: a page of tables and plots inks well over 2 % of its pixels in
  // many colours (a white page: 0 % and 1 colour).
  CHECK(view.inked_fraction > 0.02);
  CHECK(view.colours > 20);
}

// A small tissue with every kind of output a report shows: traces of two
// variables, tissue picture, activation map, 2 snapshots.
json small_tissue_manifest() {
  return json::parse(R"({"fibrodem": 1, "name": "report_tissue", "duration_ms": 30, "seed": 3,
    "tissue": {"builder": "in_series", "width_mm": 0.2, "height_mm": 0.6, "fm_ratio": 0.3},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_f_nS": 1},
    "stimulus": [{"target": {"y_min_frac": 0.8, "type": "myocyte"}, "start_ms": 5, "duration_ms": 2, "amplitude_pA": 3000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02},
    "output": {"traces": {"cells": [0, 1, 2], "variables": ["V", "dt_ms"], "every_ms": 0.5},
               "tissue_picture": true, "maps": true,
               "snapshots": {"every_ms": 10, "from_ms": 10, "png": true, "vtk": false}}})");
}

// The PNG pictures a run left in its folder (the report embeds each; the
// browser's screenshot, written there too, is not one of them).
std::size_t pictures_in(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    n += entry.path().extension() == ".png" && entry.path().filename() != "screenshot.png";
  return n;
}

// The pictures the report embeds: every PNG of the folder, but at most
// kMostAnimationFrames of the snapshots (the animation's frames).
std::size_t pictures_shown(const std::filesystem::path& dir) {
  std::size_t snapshots = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    snapshots += entry.path().extension() == ".png" && entry.path().filename().string().rfind("snapshot_", 0) == 0;
  return pictures_in(dir) - snapshots + std::min(snapshots, kMostAnimationFrames);
}

int run(const std::string& command) { return WEXITSTATUS(std::system((command + " > /dev/null 2>&1").c_str())); }

}  // namespace

TEST_CASE("report.html of a run opens in a browser with every plot and picture drawn") {
  const std::string browser = chromium();
  if (browser.empty()) {
    std::puts(kSkipMessage);
    return;
  }
  const auto dir = testing::scratch_dir("report_browser_run");
  std::ofstream(dir / "m.json") << small_tissue_manifest().dump();
  REQUIRE(run(kFibrodem + " run --quiet " + (dir / "m.json").string() + " --out " + (dir / "out").string()) == 0);
  // Plots: the biomarker histograms, one per traced variable (V, dt_ms).
  // Pictures: tissue, activation map, 3 snapshots (t = 10, 20, 30 ms).
  REQUIRE(pictures_in(dir / "out") == 5);
  check_drawn(open_in_browser(browser, dir / "out" / "report.html"), 3, 5,
              {"Biomarker histograms", "V", "dt_ms", "Tissue by cell type", "Activation map", "Membrane potential"},
              "fibrodem run: report_tissue");
}

TEST_CASE("report.html of an interrupted run, and of a folder without summary.json, open in a browser") {
  const std::string browser = chromium();
  if (browser.empty()) {
    std::puts(kSkipMessage);
    return;
  }
  const auto dir = testing::scratch_dir("report_browser_interrupted");
  json slow = small_tissue_manifest();
  slow["duration_ms"] = 1e7;  // far longer than the test waits
  std::ofstream(dir / "slow.json") << slow.dump();
  const auto out = dir / "out";
  REQUIRE(run("timeout --preserve-status -s TERM 2 " + kFibrodem + " run --quiet " + (dir / "slow.json").string() +
              " --out " + out.string()) == 143);
  // Written at the end of the interrupted run, and again by `fibrodem report`.
  REQUIRE(std::filesystem::exists(out / "report.html"));
  std::filesystem::remove(out / "report.html");
  REQUIRE(run(kFibrodem + " report " + out.string()) == 0);
  const std::string page = testing::read_file(out / "report.html");
  CHECK(page.find("<div class=\"notice warning\"><strong>interrupted at t = ") != std::string::npos);
  // Before its first beat ends the interrupted run may hold no histogram:
  // count what the page says it drew.
  const BrowserView view = open_in_browser(browser, out / "report.html");
  const std::size_t histograms = page.find("<figcaption>Biomarker histograms") != std::string::npos;
  // Every picture written before the signal: tissue, map, the snapshots.
  REQUIRE(pictures_in(out) >= 3);
  check_drawn(view, histograms + 2, pictures_shown(out), {"V", "dt_ms", "Tissue by cell type", "Membrane potential"}, "fibrodem run: report_tissue");

  // Killed before summary.json was written: the report says so, and shows
  // what is there.
  std::filesystem::remove(out / "summary.json");
  REQUIRE(run(kFibrodem + " report " + out.string()) == 0);
  CHECK(testing::read_file(out / "report.html").find("no summary.json") != std::string::npos);
  check_drawn(open_in_browser(browser, out / "report.html"), histograms + 2, pictures_shown(out), {"V", "dt_ms"}, "fibrodem run: out");
}

TEST_CASE("sweep/report.html opens in a browser with the metrics plotted against the grid") {
  const std::string browser = chromium();
  if (browser.empty()) {
    std::puts(kSkipMessage);
    return;
  }
  const auto dir = testing::scratch_dir("report_browser_sweep");
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 20;
  std::ofstream(dir / "base.json") << m.dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "set": {"stimulus[0].duration_ms": 5}, "grid": {"stimulus[0].amplitude_pA": [1, 2, 3]}, "seeds": 2})";
  REQUIRE(run(kFibrodem + " sweep " + (dir / "sweep.json").string() + " --out " + (dir / "out").string() +
              " --jobs 2") == 0);
  // One SVG holding every metric's panel; no pictures.
  check_drawn(open_in_browser(browser, dir / "out" / "report.html"), 1, 0, {"sweep: mean over the seeds"},
              "fibrodem sweep: out");
  CHECK(std::filesystem::exists(dir / "out" / "run_0" / "report.html"));
}

TEST_CASE("compare/report.html opens in a browser with A and B side by side") {
  const std::string browser = chromium();
  if (browser.empty()) {
    std::puts(kSkipMessage);
    return;
  }
  const auto dir = testing::scratch_dir("report_browser_compare");
  std::ofstream(dir / "m.json") << small_tissue_manifest().dump();
  REQUIRE(run(kFibrodem + " compare --quiet " + (dir / "m.json").string() +
              " --a coupling.D_f_nS=0.5 --b coupling.D_f_nS=4 --out " + (dir / "out").string()) == 0);
  // Traces: the 4 columns both traced (V of 3 cells, the step dt_ms);
  // pictures: tissue and activation map of A and of B.
  check_drawn(open_in_browser(browser, dir / "out" / "report.html"), 4, 4,
              {"V_0", "V_2", "dt_ms", "A", "B"}, "fibrodem compare: A and B");
}

TEST_CASE("report.html of a run with output.reentry opens in a browser with its maps and the animation") {
  const std::string browser = chromium();
  if (browser.empty()) {
    std::puts(kSkipMessage);
    return;
  }
  const auto dir = testing::scratch_dir("report_browser_reentry");
  json m = small_tissue_manifest();
  m["output"]["reentry"] = {{"every_ms", 1}, {"tau_ms", 10}};
  m["duration_ms"] = 60;  // a beat that spreads: the whole sheet stimulated
  m["stimulus"][0]["target"] = "myocyte";
  m["stimulus"][0]["amplitude_pA"] = 6000;
  std::ofstream(dir / "m.json") << m.dump();
  REQUIRE(run(kFibrodem + " run --quiet " + (dir / "m.json").string() + " --out " + (dir / "out").string()) == 0);
  const std::string page = testing::read_file(dir / "out" / "report.html");
  CHECK(page.find("onclick=\"fibrodemPlay(") != std::string::npos);
  // Plots: histograms, V, dt_ms, and the PS trajectories if any. Pictures:
  // every PNG of the folder (tissue, activation map, 6 snapshots, the
  // dominant-frequency map, one map per beat).
  const std::size_t ps_plot = page.find("No phase singularity") == std::string::npos;
  REQUIRE(std::filesystem::exists(dir / "out" / "dominant_frequency_map.png"));
  check_drawn(open_in_browser(browser, dir / "out" / "report.html"), 3 + ps_plot, pictures_shown(dir / "out"),
              {"Dominant frequency per cell", "Activation map per beat", "Membrane potential"},
              "fibrodem run: report_tissue");
}

TEST_SUITE_END();
