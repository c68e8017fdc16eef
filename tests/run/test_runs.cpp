// Whole runs: determinism, outputs written as they go, blow-ups stopped and
// named, explicit and implicit coupling agreeing, and only what is needed built.
#include <doctest/doctest.h>

#include <cmath>
#include <csignal>
#include <regex>
#include <sstream>
#include <tuple>

#include "run/interrupt.hpp"
#include "run/resource_estimate.hpp"
#include "support/scenes.hpp"
#include "tissue/coordinate_bisection.hpp"

using namespace fibrodem;

namespace {
json passive_strand(int cells, double D_f_nS) {
  json m = testing::passive_cell_manifest();
  m["tissue"] = {{"builder", "strand"}, {"type", "fibroblast"}, {"cells", cells}};
  m["coupling"] = {{"D_f_nS", D_f_nS}};
  m["stimulus"] = json::array({{{"target", {0}}, {"start_ms", 10}, {"duration_ms", 20}, {"amplitude_pA", 20},
                                {"period_ms", 50}}});
  m["output"]["traces"] = {{"cells", {0, cells - 1}}, {"variables", {"V", "I_ion"}}, {"every_ms", 0.5}};
  return m;
}

void run_to(json m, const std::filesystem::path& dir) {
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
}
}  // namespace

TEST_CASE("the same manifest run twice gives byte-identical traces and biomarkers") {
  for (const char* method : {"euler", "rush_larsen", "cvode"}) {
    CAPTURE(method);
    json m = passive_strand(6, 1.0);
    m["solver"]["method"] = method;
    const auto a = testing::scratch_dir(std::string("det_a_") + method);
    const auto b = testing::scratch_dir(std::string("det_b_") + method);
    run_to(m, a);
    run_to(m, b);
    for (const char* file : {"traces.csv", "biomarkers.csv"}) {
      const std::string first = testing::read_file(a / file);
      CHECK(first.size() > 100);
      CHECK(first == testing::read_file(b / file));
    }
  }
}

TEST_CASE("the output directory holds what docs/reference/outputs.md names, with the summary's fields") {
  const auto dir = testing::scratch_dir("outputs");
  run_to(passive_strand(4, 1.0), dir);
  for (const char* file : {"summary.json", "biomarkers.csv", "traces.csv", "run.log"})
    CHECK(std::filesystem::exists(dir / file));
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  CHECK(summary["status"] == "completed");
  CHECK(summary["cells"]["fibroblast"] == 4);
  CHECK(summary["plugins"][0]["name"] == "passive_fibroblast");
  CHECK(summary["plugins"][0]["sha256"].get<std::string>().size() == 64);
  CHECK(summary["effects"] == json({"electrophysiology", "coupling"}));
  CHECK(summary["mean_biomarkers"]["fibroblast"]["beats_measured"] == 4 * 2);
  CHECK(testing::read_file(dir / "traces.csv").rfind("t_ms,V_0,I_ion_0,V_3,I_ion_3\n", 0) == 0);
  CHECK(testing::read_file(dir / "biomarkers.csv")
            .rfind("cell,type,beat,activation_ms,rmp_mV,apo_mV,apd90_ms,dvdt_max_mV_per_ms,apd50_ms\n", 0) == 0);
  const std::string log = testing::read_file(dir / "run.log");
  CHECK(log.find("process built: coupling") != std::string::npos);
}

TEST_CASE("explicit Euler past its stability limit stops with a named blow-up and keeps its outputs") {
  // D_f = 1000 nS on 6.3 pF: lambda <= 2 * 2000 / 6.3 = 635 /ms, so explicit
  // coupling needs dt < 2/lambda = 0.003 ms; dt = 0.05 ms must blow up.
  json m = passive_strand(8, 1000.0);
  m["solver"]["dt_ms"] = 0.05;
  m["duration_ms"] = 100;
  const auto dir = testing::scratch_dir("blowup");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  try {
    sim.run();
    FAIL("expected the run to fail");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.find("blow-up at t = ") != std::string::npos);
    CHECK(message.find("model passive_fibroblast") != std::string::npos);
    CHECK(message.find("state 'V'") != std::string::npos);
    CHECK(message.find("smaller solver.dt_ms") != std::string::npos);
  }
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  CHECK(summary["status"] == "failed");
  CHECK(summary["error"].get<std::string>().find("blow-up") != std::string::npos);
  const std::string traces = testing::read_file(dir / "traces.csv");
  CHECK(traces.find("nan") == std::string::npos);
  CHECK(std::count(traces.begin(), traces.end(), '\n') > 2);  // what was written stays
  CHECK(testing::read_file(dir / "run.log").find("stability limit of explicit coupling") != std::string::npos);
}

TEST_CASE("implicit coupling is stable where explicit is not, and agrees with a fine explicit run") {
  json fine = passive_strand(8, 1000.0);
  fine["solver"]["dt_ms"] = 0.001;
  fine["duration_ms"] = 60;
  Simulation reference(parse_scene(fine));
  reference.run();

  json coarse = fine;
  coarse["solver"]["dt_ms"] = 0.05;
  coarse["coupling"]["scheme"] = "implicit";
  Simulation implicit(parse_scene(coarse));
  implicit.run();
  const auto& Vr = reference.trace("V", 7);
  const auto& Vi = implicit.trace("V", 7);
  REQUIRE(Vr.size() == Vi.size());
  double worst = 0, swing = 0;
  for (std::size_t k = 0; k < Vr.size(); ++k) {
    worst = std::max(worst, std::abs(Vr[k] - Vi[k]));
    swing = std::max(swing, std::abs(Vr[k] + 49.6));
  }
  // Splitting error O(dt): within 1 % of the response's swing at dt = 0.05 ms.
  CHECK(swing > 1.0);
  CHECK(worst < 0.01 * swing);
}

TEST_CASE("without coupling the cells of a strand do not talk, the log says why") {
  json m = passive_strand(3, 5.0);
  m["effects"] = {"electrophysiology"};
  Simulation sim(parse_scene(m));
  sim.run();
  CHECK_FALSE(sim.processes().has("coupling"));
  CHECK(sim.trace("V", 2).back() == -49.6);  // never stimulated, never coupled
  REQUIRE(!sim.processes().notes.empty());
  CHECK(sim.processes().notes[0].find("coupling not built") != std::string::npos);
}

TEST_CASE("an effect the scene cannot support is refused with what it needs") {
  json m = testing::passive_cell_manifest();
  m["effects"] = {"electrophysiology", "mechanics"};  // mechanics needs contraction, which needs a myofilament model
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(m)), doctest::Contains("myofilament"), ManifestError);
}

TEST_CASE("results do not depend on the thread count" * doctest::test_suite("threads")) {
  // 2100 cells: nine blocks of cells, cut between the threads at measured
  // costs (inside a block) and taken over by a thread done early, each piece
  // computing its own gap-junction currents inside the parallel loop; the
  // biomarkers of most steps measured on the same threads. Pictures and
  // snapshots are written on the writer's thread with a core to spare (1
  // thread on 2 cores), else by the run's own thread: the same files.
  json m = json::parse(R"({
    "fibrodem": 1, "name": "threads", "duration_ms": 6,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 2100},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0, 1, 2, 3], "start_ms": 1, "duration_ms": 2, "amplitude_pA": 8000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0, 100, 2099], "variables": ["V", "Ca_i"], "every_ms": 0.1},
               "snapshots": {"every_ms": 2, "vtk": true}, "tissue_picture": true}
  })");
  std::string first;
  for (int threads : {1, 2, 3}) {
    CAPTURE(threads);
    m["solver"]["threads"] = threads;
    const auto dir = testing::scratch_dir("threads_" + std::to_string(threads));
    run_to(m, dir);
    std::string traces = testing::read_file(dir / "traces.csv") + testing::read_file(dir / "biomarkers.csv");
    for (const char* t : {"0.010", "2.000", "4.000", "6.000"}) {
      CHECK(std::filesystem::exists(dir / ("snapshot_0000" + std::string(t) + "_ms.png")));
      traces += testing::read_file(dir / ("snapshot_0000" + std::string(t) + "_ms.vtk"));
    }
    CHECK(std::filesystem::exists(dir / "tissue.png"));
    if (first.empty()) first = traces;
    CHECK(traces == first);
  }
}

TEST_CASE("SIGTERM or SIGINT ends a run at the end of a step: outputs written, status interrupted, exit 143 / 130" * doctest::test_suite("threads")) {
  // In the library: as if the signal had come during the run.
  const auto dir = testing::scratch_dir("interrupted");
  json m = testing::passive_cell_manifest();
  m["output"]["dir"] = (dir / "lib").string();
  Simulation sim(parse_scene(m));
  request_interrupt(SIGTERM);
  try {
    sim.run();
    request_interrupt(0);
    FAIL("expected the run to stop");
  } catch (const InterruptedError& e) {
    request_interrupt(0);
    CHECK(e.signal() == SIGTERM);
    CHECK(std::string(e.what()).find("interrupted by SIGTERM at t = 0.01 ms") != std::string::npos);
  }
  const json summary = json::parse(testing::read_file(dir / "lib" / "summary.json"));
  CHECK(summary["status"] == "interrupted");
  CHECK(summary["simulated_ms"].get<double>() == doctest::Approx(0.01));
  CHECK(testing::read_file(dir / "lib" / "run.log").find("run interrupted: 0.01 of 100 ms") != std::string::npos);

  // The command line, killed while it runs: exit 128 + signal, files complete.
  for (const auto& [signal, name, code] : {std::tuple{SIGTERM, "TERM", 143}, std::tuple{SIGINT, "INT", 130}}) {
    const std::string signal_text = name;  // (clang 14 cannot capture a structured binding)
    CAPTURE(signal_text);
    json slow = testing::passive_cell_manifest();
    slow["duration_ms"] = 1e7;  // far longer than the test waits
    slow["solver"]["dt_ms"] = 0.001;
    const auto out = dir / name;
    std::ofstream(dir / "slow.json") << slow.dump();
    // Signalled once the run has started (its first summary.json written),
    // not after a fixed time: a slow start (a sanitizer build under load)
    // would otherwise be killed before there is a run to end.
    const std::string summary_file = (out / "summary.json").string();
    const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem run --quiet " + (dir / "slow.json").string() +
                                " --out " + out.string() + " > /dev/null 2>&1 & pid=$!; i=0; while [ ! -s " +
                                summary_file + " ] && [ $i -lt 2400 ]; do sleep 0.05; i=$((i + 1)); done; sleep 0.2; kill -" +
                                std::string(name) + " $pid; wait $pid";
    const int status = std::system(command.c_str());
    CHECK(WEXITSTATUS(status) == code);
    const json s = json::parse(testing::read_file(out / "summary.json"));
    CHECK(s["status"] == "interrupted");
    CHECK(s["simulated_ms"].get<double>() > 0);
    CHECK(testing::read_file(out / "run.log").find("run interrupted") != std::string::npos);
    CHECK(testing::read_file(out / "traces.csv").find("t_ms") == 0);
  }
}

TEST_CASE("output folder problems are found before any computation, naming the folder and the reason") {
  const auto dir = testing::scratch_dir("output_problems");
  json m = testing::passive_cell_manifest();
  auto set_up = [&](const std::filesystem::path& out, bool overwrite = false) {
    Scene scene = parse_scene(m);
    scene.output.dir = out.string();
    scene.output.overwrite = overwrite;
    return std::make_unique<Simulation>(scene);
  };
  // A file where the folder should be.
  std::ofstream(dir / "a_file") << "x";
  CHECK_THROWS_WITH_AS(set_up(dir / "a_file"), doctest::Contains("cannot create the output folder"), ManifestError);
  CHECK_THROWS_WITH_AS(set_up(dir / "a_file" / "below"), doctest::Contains((dir / "a_file").string().c_str()), ManifestError);
  // A folder nobody can write into, not even root (procfs).
  CHECK_THROWS_WITH_AS(set_up("/proc/self"), doctest::Contains("cannot write into the output folder"), ManifestError);
  // Another run's files: refused unless overwriting is asked for.
  set_up(dir / "done")->run();
  CHECK_THROWS_WITH_AS(set_up(dir / "done"), doctest::Contains("holds another run's files"), ManifestError);
  CHECK_NOTHROW(set_up(dir / "done", true)->run());
}

TEST_CASE("a write that fails (a full disk) stops the run as failed, with the files written so far kept") {
  const auto dir = testing::scratch_dir("disk_full");
  // traces.csv on /dev/full: every write to it fails with ENOSPC.
  std::filesystem::create_symlink("/dev/full", dir / "traces.csv");
  json m = testing::passive_cell_manifest();
  m["duration_ms"] = 3000;  // long enough for the once-a-second flush... or the final one
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  CHECK_THROWS_WITH(sim.run(), doctest::Contains("traces.csv failed (is the disk full?)"));
  const json summary = json::parse(testing::read_file(dir / "summary.json"));
  CHECK(summary["status"] == "failed");
  CHECK(testing::read_file(dir / "run.log").find("run failed") != std::string::npos);
}

TEST_CASE("a scene too large for the machine is refused at set-up with the estimate and what to change") {
  json m = testing::passive_cell_manifest();
  // 10^4 s traced every 10^-4 ms: 10^11 samples, far beyond any memory.
  m["duration_ms"] = 1e7;
  m["output"]["traces"]["every_ms"] = 1e-4;
  m["solver"]["dt_ms"] = 1e-4;
  try {
    Simulation sim(parse_scene(m));
    FAIL("expected the scene to be refused");
  } catch (const ManifestError& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.find("resources") != std::string::npos);
    CHECK(message.find("traces: 1 columns x") != std::string::npos);
    CHECK(message.find("a larger every_ms") != std::string::npos);
  }
  // The rule itself, with given amounts: the largest part and its remedy.
  ResourceEstimate estimate;
  estimate.memory = {{"cell states", 1e6, "a smaller tissue"}, {"CVODE dense Jacobian", 8e9, "a band solver"}};
  estimate.output = {{"traces.csv", 5e9, "fewer cells"}};
  CHECK_NOTHROW(check_resources(estimate, 1e11, 1e11));
  CHECK_THROWS_WITH(check_resources(estimate, 4e9, 1e11), doctest::Contains("CVODE dense Jacobian (8 GB): try a band solver"));
  CHECK_THROWS_WITH(check_resources(estimate, 1e11, 1e9), doctest::Contains("more than the 1 GB free on the output disk"));
  // A scene that fits says what it needs.
  Simulation fits(parse_scene(testing::passive_cell_manifest()));
  CHECK(fits.resource_estimate().find("memory ~") == 0);
}

// A rank of a split run holds every cell, its centre and graph while the
// partition is cut (resource_estimate.cpp): with Scotch also its copies of
// the graph, 104 bytes a cell (measured with heaptrack on the 846,279-cell
// sheet: 88 MB), which set a rank's peak from 16 ranks on that sheet; with
// rcb every cell's part (4 bytes a cell) and the centres it collects at
// once (CoordinateCuts::kCollectBudget, kCandidateBytes each). A rank with no
// cells of its own to step (an empty system) shows the set-up alone.
TEST_CASE("validate counts a split rank's set-up: the cells' build and the partitioner's work") {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "split_set_up", "duration_ms": 10,
    "tissue": {"builder": "fibrotic_sheet", "width_mm": 1, "length_mm": 3},
    "cells": {"myocyte": {"model": "colman"}},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01}
  })");
  const auto set_up_bytes = [&](const char* method) {
    m["solver"]["partition"] = method;
    const Scene scene = parse_scene(m);
    const Tissue tissue = scene.tissue->build_cells(scene.seed);
    const ResourceEstimate estimate = estimate_resources(scene, tissue, CellSystem(), false, 1, 8);
    for (const auto& part : estimate.memory)
      if (part.what.rfind("the set-up", 0) == 0) return part.bytes;
    return 0.0;
  };
  const double cells = 966;  // (the 1 x 3 mm sheet's)
  const double rcb = set_up_bytes("rcb"), scotch = set_up_bytes("scotch");
  CHECK(rcb > 0);
  const double collected = CoordinateCuts::kCandidateBytes * CoordinateCuts::kCollectBudget;
  CHECK(scotch - rcb == doctest::Approx((104 - 4) * cells - collected));
}

TEST_CASE("the estimate of the snapshots' size bounds what is written, within a factor of ten") {
  // A 400-cell myocyte strand with snapshots as PNG and compressed VTK XML:
  // the estimate (resource_estimate.cpp: at most 33 bytes a particle before
  // zlib, ~8 a particle of PNG) is an upper bound, and not so loose that the
  // disk check would refuse a scene that fits (a 5 x 5 cm sheet's frames are
  // ~6 bytes a particle; the estimate once said 54 GB for its 1.8 GB).
  json m = json::parse(R"({
    "fibrodem": 1, "name": "snapshot_sizes", "duration_ms": 4,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 400},
    "cells": {"myocyte": {"model": "courtemanche", "variant": "paced_1hz"}},
    "stimulus": [{"target": [0, 1], "start_ms": 0.5, "duration_ms": 2, "amplitude_pA": 8000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"snapshots": {"every_ms": 1, "vtk": true}, "vtk_format": "xml", "report": false}
  })");
  const auto dir = testing::scratch_dir("snapshot_sizes");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  const std::string estimate = sim.resource_estimate();
  sim.run();
  std::smatch found;
  REQUIRE(std::regex_search(estimate, found, std::regex(R"((\d+) snapshots ([0-9.e+]+) (kB|MB|GB))")));
  const double unit = found[3] == "kB" ? 1e3 : found[3] == "MB" ? 1e6 : 1e9;
  const double estimated = std::stod(found[2]) * unit;
  double written = 0;
  int frames = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string().rfind("snapshot_", 0) == 0) {
      written += static_cast<double>(entry.file_size());
      frames += entry.path().extension() == ".vtp";
    }
  CAPTURE(estimate);
  CAPTURE(written);
  CHECK(frames == std::stoi(found[1]));
  CHECK(estimated >= written);
  CHECK(estimated <= 10 * written);
}

TEST_CASE("the scale examples' stimulus starts a wave: every myocyte of a 3 x 3 mm crop fires") {
  // examples/scale/sheet_*.json pace a 0.2 mm band along one edge of a sheet
  // coupled at the default D_m; the band loses its current to the sheet, so a
  // pulse too weak leaves the whole sheet at rest (4000 pA for 2 ms reached
  // -51 mV). A crop of the same sheet, paced the same way, must fire every
  // myocyte (overshoot above 0 mV).
  for (const char* name : {"sheet_2p5cm.json", "sheet_5cm.json"}) {
    CAPTURE(name);
    json m = json::parse(testing::read_file(std::filesystem::path(FIBRODEM_SOURCE_DIR) / "examples" / "scale" / name));
    m["tissue"]["width_mm"] = 3;
    m["tissue"]["length_mm"] = 3;
    m["stimulus"][0]["target"]["x_max_mm"] = 3;
    m["duration_ms"] = 60;
    m["output"] = {{"report", false}};
    const auto dir = testing::scratch_dir(std::string("scale_crop_") + name);
    run_to(m, dir);
    std::istringstream csv(testing::read_file(dir / "biomarkers.csv"));
    std::string line;
    std::getline(csv, line);  // header: cell,type,beat,activation_ms,rmp_mV,apo_mV,...
    int myocytes = 0, fired = 0;
    while (std::getline(csv, line)) {
      std::vector<std::string> cells;
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
      if (cells.size() < 6 || cells[1] != "myocyte") continue;
      ++myocytes;
      fired += !cells[5].empty() && std::stod(cells[5]) > 0;
    }
    CHECK(myocytes > 2000);
    CHECK(fired == myocytes);
  }
}

TEST_CASE("output.traces as a list of blocks: a fibroblast-only variable beside the myocyte's, one time axis") {
  const auto dir = testing::scratch_dir("trace_blocks");
  json m = json::parse(R"({"fibrodem": 1, "name": "pair", "duration_ms": 4,
    "tissue": {"builder": "cell_pair", "fibroblasts": 1},
    "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_f_nS": 1},
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "output": {"traces": [{"cells": [0], "variables": ["V", "Ca_i"], "every_ms": 1},
                          {"cells": [1], "variables": ["V", "I_Kv"]}]}})");
  m["output"]["dir"] = dir.string();
  Simulation sim(parse_scene(m));
  sim.run();
  const std::string csv = testing::read_file(dir / "traces.csv");
  CHECK(csv.substr(0, csv.find('\n')) == "t_ms,V_0,Ca_i_0,V_1,I_Kv_1");
  CHECK(sim.trace_times().size() == 5);  // 0, 1, 2, 3, 4 ms: the first block's every_ms for all
  // I_Kv is an output of maleckar_active2 alone (`fibrodem plugins`): as one
  // block over both cells it is refused for cell 0, the myocyte, naming it.
  m["output"].erase("dir");  // the checks below write nothing
  json single = m;
  single["output"]["traces"] = {{"cells", {0, 1}}, {"variables", {"V", "I_Kv"}}};
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(single)), doctest::Contains("output.traces.variables[1]"), ManifestError);
  // Blocks disagreeing on the time axis, and an unknown variable in the second block, are named.
  json clash = m;
  clash["output"]["traces"][1]["every_ms"] = 0.5;
  CHECK_THROWS_WITH_AS(parse_scene(clash), doctest::Contains("output.traces[1].every_ms: expected 1.0 as output.traces[0].every_ms gives"),
                       ManifestError);
  json unknown = m;
  unknown["output"]["traces"][1]["variables"] = {"V", "no_such_state"};
  CHECK_THROWS_WITH_AS(Simulation(parse_scene(unknown)), doctest::Contains("output.traces[1].variables[1]"), ManifestError);
}
