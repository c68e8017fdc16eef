// scripts/paper.sh --quick (the Fig. 4 and 6 sweeps at reduced size, default
// and brocklehurst2022_tissue, then scripts/paper_report.py) and `fibrodem plot`.
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/scenes.hpp"

using namespace fibrodem;

namespace {

// The cells of sweep_stats.csv's row whose first column is `at`, by header name.
std::map<std::string, std::string> stats_row(const std::filesystem::path& file, const std::string& at) {
  std::istringstream csv(testing::read_file(file));
  std::string line;
  std::vector<std::string> header;
  std::getline(csv, line);
  for (std::stringstream h(line); std::getline(h, line, ',');) header.push_back(line);
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    for (std::stringstream r(line); std::getline(r, line, ',');) cells.push_back(line);
    if (!cells.empty() && cells[0] == at) {
      std::map<std::string, std::string> row;
      for (std::size_t i = 0; i < cells.size() && i < header.size(); ++i) row[header[i]] = cells[i];
      return row;
    }
  }
  FAIL("no row " << at << " in " << file);
  return {};
}

}  // namespace

TEST_CASE("scripts/paper.sh --quick tabulates Figs. 4 and 6 for the default and brocklehurst2022_tissue" * doctest::test_suite("slow")) {
  const auto dir = testing::scratch_dir("paper_quick");
  const std::string command = "FIBRODEM_BIN=" + std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " +
                              std::string(FIBRODEM_SOURCE_DIR) + "/scripts/paper.sh --quick " + (dir / "out").string() +
                              " " + (dir / "docs").string() + " > " + (dir / "log.txt").string() + " 2>&1";
  REQUIRE(std::system(command.c_str()) == 0);
  const std::string readme = testing::read_file(dir / "docs" / "README.md");
  // Every stated value of Figs. 4 and 6 (41 of paper_values.csv's 47; Figs. 5, 7
  // are mechanics, not run by --quick) has a row with both models.
  CHECK(readme.find("**Default: ") != std::string::npos);
  CHECK(readme.find("of 41 stated values agree. `brocklehurst2022_tissue` (Figs. 4 and 6): ") != std::string::npos);
  CHECK(readme.find("| 4c | tissue.fm_ratio = 0.11 | myocyte_rmp_mV | -65.2 | ") != std::string::npos);
  CHECK(readme.find("| 6j | fm_ratio = 1.27 (nearest: ") != std::string::npos);
  for (const char* sweep : {"fig4_fm_ratio", "fig4_D_f", "fig6_fm_ratio", "fig6_D_f"}) {
    CAPTURE(sweep);
    CHECK(std::filesystem::file_size(dir / "docs" / (std::string(sweep) + "_vs_paper.png")) > 10000);
  }
  // The calibration holds on the reduced strip: the preset's myocytes rest at
  // the paper's -65.2 mV at F-M 0.11 (calibrated to -65.20 on this strip,
  // seed 1); the default's at -74.9 (docs/paper, 5 full-width tissues: -74.91).
  const auto preset = stats_row(dir / "out" / "brocklehurst2022_tissue" / "fig4_fm_ratio" / "sweep_stats.csv", "0.11");
  const auto standard = stats_row(dir / "out" / "fig4_fm_ratio" / "sweep_stats.csv", "0.11");
  CHECK(std::stod(preset.at("myocyte_rmp_mV_mean")) == doctest::Approx(-65.2).epsilon(0.005));
  CHECK(std::stod(standard.at("myocyte_rmp_mV_mean")) == doctest::Approx(-74.9).epsilon(0.005));
}

TEST_CASE("fibrodem plot draws a JSON spec and names what is wrong in a bad one") {
  const auto dir = testing::scratch_dir("plot");
  const std::string fibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem plot ";
  std::ofstream(dir / "good.json") << R"({"title": "t", "panels": [{"title": "a", "x_label": "x", "y_label": "y",
      "series": [{"label": "s", "x": [1, 2, 3], "y": [1, null, 3], "y_low": [0, 0, 2], "y_high": [2, 2, 4]}]}]})";
  REQUIRE(std::system((fibrodem + (dir / "good.json").string() + " --out " + (dir / "good.png").string()).c_str()) == 0);
  CHECK(testing::read_file(dir / "good.png").substr(1, 3) == "PNG");
  std::ofstream(dir / "bad.json") << R"({"panels": [{"series": [{"x": [1, 2], "y": [1, "a"]}]}]})";
  const int status = std::system((fibrodem + (dir / "bad.json").string() + " --out " + (dir / "bad.png").string() +
                                  " 2> " + (dir / "bad.txt").string()).c_str());
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(testing::read_file(dir / "bad.txt").find("panels[0].series[0].y[1]: expected a number or null, got \"a\"") !=
        std::string::npos);
  std::ofstream(dir / "short.json") << R"({"panels": [{"series": [{"x": [1, 2], "y": [1]}]}]})";
  CHECK(WEXITSTATUS(std::system((fibrodem + (dir / "short.json").string() + " --out " + (dir / "s.png").string() +
                                 " 2> /dev/null").c_str())) == 2);
  CHECK_FALSE(std::filesystem::exists(dir / "bad.png"));
}
