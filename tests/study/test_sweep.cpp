// `fibrodem sweep`: one run per grid point, tabulated.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sys/wait.h>

#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_CASE("a sweep runs every grid point and tabulates mean biomarkers" * doctest::test_suite("threads")) {
  const auto dir = testing::scratch_dir("sweep");
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 20;
  std::ofstream(dir / "base.json") << m.dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "set": {"stimulus[0].duration_ms": 5},
      "grid": {"stimulus[0].amplitude_pA": [10, 20], "cells.fibroblast.parameters.R_GOhm": [5, 10]}})";
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem sweep " + (dir / "sweep.json").string() +
                              " --out " + (dir / "out").string() + " --jobs 2 > /dev/null 2>&1";
  REQUIRE(std::system(command.c_str()) == 0);
  std::istringstream csv(testing::read_file(dir / "out" / "sweep.csv"));
  std::string header, line;
  std::getline(csv, header);
  CHECK(header.rfind("run,cells.fibroblast.parameters.R_GOhm,stimulus[0].amplitude_pA,", 0) == 0);
  std::vector<double> apo;
  while (std::getline(csv, line)) {
    // Passive response to I for 5 ms: the peak rises with I R (columns 8.. are fibroblast means).
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    // run, 2 grid values, F-M, 2 x 4 means, CV, 2 peak strains, 2 re-entry, 2 not-fired fractions, status
    REQUIRE(cells.size() == 20);
    CHECK(cells[18] == "0");  // the fibroblast rose 7 mV or more: it fired (1 pA, 0.7 mV, would not)
    CHECK(cells.back() == "completed");
    apo.push_back(std::stod(cells[9]) - std::stod(cells[8]));  // fibroblast APO - RMP
  }
  REQUIRE(apo.size() == 4);
  // Order: R 5 (I 1, 2), R 10 (I 1, 2): the rise is proportional to I R (1 - exp(-5/(R C))).
  CHECK(apo[1] == doctest::Approx(2 * apo[0]).epsilon(1e-6));
  CHECK(apo[3] == doctest::Approx(2 * apo[2]).epsilon(1e-6));
  CHECK(apo[2] > apo[0]);
  CHECK(std::filesystem::exists(dir / "out" / "run_3" / "summary.json"));
}

TEST_CASE("a sweep point that crashes its process (a segfaulting plugin) leaves the other points to finish" * doctest::test_suite("threads")) {
  const auto dir = testing::scratch_dir("sweep_crash");
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 5;
  m["cells"]["fibroblast"]["model"] = "misbehaves";
  std::ofstream(dir / "base.json") << m.dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "grid": {"cells.fibroblast.parameters.fault": [0, 2, 0]}})";
  const std::string command = "FIBRODEM_PLUGIN_PATH=" + std::string(FIBRODEM_BINARY_DIR) + "/test_plugins " +
                              std::string(FIBRODEM_BINARY_DIR) + "/fibrodem sweep " + (dir / "sweep.json").string() +
                              " --out " + (dir / "out").string() + " --jobs 2 > /dev/null 2>&1";
  const int exit_status = std::system(command.c_str());
  CHECK(WEXITSTATUS(exit_status) == 4);  // the sweep completes, saying a point did not
  const std::string csv = testing::read_file(dir / "out" / "sweep.csv");
  CAPTURE(csv);
  std::istringstream rows(csv);
  std::string header, line;
  std::getline(rows, header);
  std::vector<std::string> status;
  while (std::getline(rows, line)) status.push_back(line.substr(line.rfind(',') + 1));
  REQUIRE(status.size() == 3);
  CHECK(status[0] == "completed");
  CHECK(status[2] == "completed");
  // Killed by SIGSEGV; under AddressSanitizer its handler reports the fault
  // and exits instead, and the point is "failed" with that exit status.
  const std::string md = testing::read_file(dir / "out" / "sweep.md");
  if (status[1] == "crashed") CHECK(md.find("signal 11") != std::string::npos);
  else CHECK(status[1] == "failed");
}

namespace {

// A small in-series tissue whose random layout changes with the seed, every
// cell fired by the stimulus (at 3000 pA none was: the means were of cells at rest).
json seeded_manifest() {
  return json::parse(R"({"fibrodem": 1, "name": "seeded", "duration_ms": 30, "seed": 3,
    "tissue": {"builder": "in_series", "width_mm": 0.2, "height_mm": 0.8, "fm_ratio": 0.3},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "passive_fibroblast"}},
    "coupling": {"D_f_nS": 1},
    "stimulus": [{"target": {"y_min_frac": 0.8, "type": "myocyte"}, "start_ms": 2, "duration_ms": 2, "amplitude_pA": 6000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.02}})");
}

int sweep(const std::filesystem::path& file, const std::filesystem::path& out, const std::string& extra = "",
          const std::string& launcher = "") {
  const std::string command = launcher + std::string(FIBRODEM_BINARY_DIR) + "/fibrodem sweep " + file.string() +
                              " --out " + out.string() + " " + extra + " > " + out.string() + ".txt 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Rows of a CSV file as cells (no quoting in fibrodem's tables).
using testing::csv_rows;

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  REQUIRE(it != header.end());
  return static_cast<std::size_t>(it - header.begin());
}

}  // namespace

TEST_CASE("sweep seeds: every grid point over K tissues, with mean, SD and 95 % CI checked by hand" * doctest::test_suite("threads")) {
  const auto dir = testing::scratch_dir("sweep_seeds");
  std::ofstream(dir / "base.json") << seeded_manifest().dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "grid": {"coupling.D_f_nS": [0.5, 4]}, "seeds": 3})";
  REQUIRE(sweep(dir / "sweep.json", dir / "out") == 0);
  const auto runs = csv_rows(dir / "out" / "sweep.csv");
  REQUIRE(runs.size() == 1 + 2 * 3);
  CHECK(runs[0][1] == "coupling.D_f_nS");
  CHECK(runs[0][2] == "seed");
  // Seeds 3, 4, 5 (the manifest's seed and the two after it) draw different tissues.
  const std::size_t fm = column(runs[0], "fm_ratio"), rmp = column(runs[0], "fibroblast_rmp_mV");
  CHECK(runs[1][2] == "3");
  CHECK(runs[3][2] == "5");
  CHECK((runs[1][fm] != runs[2][fm] || runs[2][fm] != runs[3][fm]));
  const auto stats = csv_rows(dir / "out" / "sweep_stats.csv");
  REQUIRE(stats.size() == 3);
  for (std::size_t point = 0; point < 2; ++point) {
    CAPTURE(point);
    // By hand: mean, sample SD, and mean +- t(0.975, 2) SD / sqrt(3), with
    // t(0.975, 2) = 4.302652729749464 (closed form for 2 degrees of freedom,
    // (2p - 1) / sqrt(2p(1 - p))).
    double x[3], mean = 0, ss = 0;
    for (int s = 0; s < 3; ++s) mean += (x[s] = std::stod(runs[1 + 3 * point + s][rmp])) / 3;
    for (double v : x) ss += (v - mean) * (v - mean);
    const double sd = std::sqrt(ss / 2), half = 4.302652729749464 * sd / std::sqrt(3.0);
    const auto& row = stats[1 + point];
    CHECK(row[column(stats[0], "seeds_completed")] == "3");
    CHECK(std::stod(row[column(stats[0], "fibroblast_rmp_mV_mean")]) == doctest::Approx(mean).epsilon(1e-12));
    CHECK(std::stod(row[column(stats[0], "fibroblast_rmp_mV_sd")]) == doctest::Approx(sd).epsilon(1e-9));
    CHECK(std::stod(row[column(stats[0], "fibroblast_rmp_mV_ci95_low")]) == doctest::Approx(mean - half).epsilon(1e-9));
    CHECK(std::stod(row[column(stats[0], "fibroblast_rmp_mV_ci95_high")]) == doctest::Approx(mean + half).epsilon(1e-9));
  }
  CHECK(std::filesystem::file_size(dir / "out" / "sweep.png") > 10000);
  CHECK(testing::read_file(dir / "out" / "sweep.md").find("Over the seeds") != std::string::npos);
}

TEST_CASE("a sweep run again skips the runs completed with the same manifest and runs the changed ones, --set works" * doctest::test_suite("threads")) {
  const auto dir = testing::scratch_dir("sweep_resume");
  std::ofstream(dir / "base.json") << seeded_manifest().dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "grid": {"coupling.D_f_nS": [0.5, 4]}})";
  REQUIRE(sweep(dir / "sweep.json", dir / "out") == 0);
  const std::string first = testing::read_file(dir / "out" / "sweep.csv");
  // The same sweep: nothing runs again, the same table.
  REQUIRE(sweep(dir / "sweep.json", dir / "out") == 0);
  CHECK(testing::read_file(dir / "out.txt").find("2 of 2 runs completed before with the same manifest") != std::string::npos);
  CHECK(testing::read_file(dir / "out" / "sweep.csv") == first);
  // One grid value changed: that run alone runs again.
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "grid": {"coupling.D_f_nS": [0.5, 2]}})";
  REQUIRE(sweep(dir / "sweep.json", dir / "out") == 0);
  CHECK(testing::read_file(dir / "out.txt").find("1 of 2 runs completed before") != std::string::npos);
  CHECK(csv_rows(dir / "out" / "sweep.csv")[2][1] == "2");
  // --set on the sweep changes every run's manifest: all run again, with it.
  REQUIRE(sweep(dir / "sweep.json", dir / "out", "--set duration_ms=20") == 0);
  CHECK(testing::read_file(dir / "out.txt").find("completed before") == std::string::npos);
  CHECK(json::parse(testing::read_file(dir / "out" / "run_0" / "summary.json"))["simulated_ms"] == 20.0);
}

TEST_CASE("mpirun -n 2 fibrodem sweep gives the same tables as a local sweep" * doctest::test_suite("mpi threads")) {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("sweep_mpi");
  std::ofstream(dir / "base.json") << seeded_manifest().dump();
  std::ofstream(dir / "sweep.json") << R"({"fibrodem_sweep": 1, "manifest": "base.json",
      "grid": {"coupling.D_f_nS": [0.5, 4], "tissue.fm_ratio": [0.1, 0.5]}, "seeds": 2})";
  REQUIRE(sweep(dir / "sweep.json", dir / "local") == 0);
  REQUIRE(sweep(dir / "sweep.json", dir / "mpi", "", testing::mpirun(2)) == 0);
  CHECK(testing::read_file(dir / "mpi.txt").find("over 2 MPI ranks") != std::string::npos);
  CHECK(testing::read_file(dir / "mpi" / "sweep.csv") == testing::read_file(dir / "local" / "sweep.csv"));
  CHECK(testing::read_file(dir / "mpi" / "sweep_stats.csv") == testing::read_file(dir / "local" / "sweep_stats.csv"));
}
