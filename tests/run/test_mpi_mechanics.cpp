// Contraction, mechano-electric feedback and the DEM mechanics in a run
// split over MPI ranks (docs/guide/parallel.md): each rank steps its own cells
// and myofilaments, and either its own cells' DEM bodies (in series) or
// sends every cell's length to rank 0, which steps the DEM for the whole
// tissue (interstitial: multirate is not split). With a fixed step and
// explicit coupling the cells' lengths have one process's bits, so the
// reference is the same scene run in one process: the same bytes (traces,
// biomarkers, deformed snapshots, summary.json's peak strain), but for the
// split DEM's strain, whose sums over every body are added rank by rank:
// within 1e-12 of its peak. With the adaptive
// method the reference is one process within the tolerances the split EP
// is held to (tests/tissue/test_mpi_tissue.cpp), and the strain within the bound
// derived below. A 2-rank EM run killed and resumed on 2 ranks writes the
// run never stopped (rank 0's checkpoint holds the DEM).
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "support/mpi_launch.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

// Every case here is labelled "mpi" for ctest (tests/CMakeLists.txt).
TEST_SUITE_BEGIN("mpi");
namespace fs = std::filesystem;

namespace {

// A sheet of contracting myocytes (Colman 2013 with Rice myofilaments)
// and active fibroblasts, the Fig. 3 EM scenes' cells, coupling and DEM
// (examples/fig3_*_em.json) on a smaller tissue, stimulated along its upper
// edge at 2 ms: in series 0.6 x 0.6 mm (146 cells, 740 particles),
// interstitial 0.3 x 1 mm (227 cells, 81 of them myocytes). On both the
// 2 ranks' cells interleave in the tissue's numbering, so a length placed
// by rank order instead of by cell number moves the strain. The strain
// (yy) reaches ~1e-5 at 40 ms; in series it peaks, ~4.7e-4, near 130 ms.
// Traced: V and the sarcomere length SL of myocytes far apart.
json em_sheet(const std::string& builder, double duration_ms) {
  json m = json::parse(R"({"fibrodem": 1, "name": "em", "seed": 3,
    "effects": ["electrophysiology", "coupling", "mechanics"],
    "cells": {"myocyte": {"model": "colman", "variant": "colman2013", "myofilament": "rice"},
              "fibroblast": {"model": "maleckar_active2"}},
    "coupling": {"D_m_nS": 1000, "D_f_nS": 0.3},
    "stimulus": [{"target": {"y_min_frac": 0.7, "type": "myocyte"}, "start_ms": 2, "duration_ms": 2,
                  "amplitude_pA": 2000}],
    "solver": {"method": "rush_larsen", "dt_ms": 0.01},
    "mechanics": {"solver": "dem", "contact_law": "linear_bond", "kn_N_per_m": 26, "ks_N_per_m": 0.26,
                  "damping_ratio_normal": 0.1, "damping_ratio_shear": 0.1, "fibroblast_stiffness_factor": 1.0},
    "output": {"traces": [{"cells": [0, 70, 145], "variables": ["V", "SL"], "every_ms": 0.5}]}})");
  m["tissue"] = {{"builder", builder}, {"width_mm", 0.6}, {"height_mm", 0.6}, {"fm_ratio", 0.41}};
  if (builder == "interstitial") {
    m["tissue"] = {{"builder", builder}, {"width_mm", 0.3}, {"height_mm", 1.0}};
    m["output"]["traces"][0]["cells"] = {0, 40, 80};
    m["mechanics"].update({{"local_damping", 0.7}, {"mass_scaling", 0.0025}, {"multirate", true}});
  }
  m["duration_ms"] = duration_ms;
  return m;
}

json summary_of(const fs::path& dir) { return json::parse(testing::read_file(dir / "summary.json")); }

using testing::csv_rows;

double number(const std::string& text) { return text.empty() ? std::nan("") : std::stod(text); }

std::set<std::string> snapshot_names(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().rfind("snapshot", 0) == 0) names.insert(entry.path().filename().string());
  return names;
}

// The strain columns (the first three after t_ms) within 1e-12 of their
// peak, every other column the same text.
void check_strain_to_rounding(const fs::path& one, const fs::path& two) {
  const auto a = csv_rows(one / "traces.csv"), b = csv_rows(two / "traces.csv");
  REQUIRE(a.size() == b.size());
  double peak = 0, largest = 0;
  for (std::size_t k = 1; k < a.size(); ++k) {
    REQUIRE(a[k].size() == b[k].size());
    for (std::size_t j = 0; j < a[k].size(); ++j) {
      if (j < 1 || j > 3) {
        CHECK(a[k][j] == b[k][j]);
        continue;
      }
      peak = std::max(peak, std::abs(number(a[k][j])));
      largest = std::max(largest, std::abs(number(a[k][j]) - number(b[k][j])));
    }
  }
  MESSAGE("strain within ", largest, " of one process's (peak ", peak, ")");
  CHECK(largest <= 1e-12 * peak);
}

// The same traces.csv, biomarkers.csv and summary.json mechanics figures;
// with the DEM split over the ranks (dem_split), the strain to rounding:
// its sums over every body are added rank by rank.
void check_same_bytes(const fs::path& one, const fs::path& two, int ranks_of_two = 2, bool dem_split = false) {
  const std::string traces = testing::read_file(one / "traces.csv");
  REQUIRE(traces.rfind("t_ms,eps_xx,eps_yy,eps_xy,V_0,SL_0,", 0) == 0);  // the strain first, as one process
  if (dem_split)
    check_strain_to_rounding(one, two);
  else
    CHECK(testing::read_file(two / "traces.csv") == traces);
  CHECK(testing::read_file(two / "biomarkers.csv") == testing::read_file(one / "biomarkers.csv"));
  const json a = summary_of(one), b = summary_of(two);
  CHECK(b["status"] == "completed");
  CHECK(b["mpi_ranks"] == ranks_of_two);
  if (dem_split)
    for (const char* k : {"xx", "yy", "xy"})
      CHECK(std::abs(b["peak_strain"][k].get<double>() - a["peak_strain"][k].get<double>()) <=
            1e-12 * std::abs(a["peak_strain"]["yy"].get<double>()));
  else
    CHECK(b["peak_strain"] == a["peak_strain"]);
  CHECK(b["mechanics_step_ms"] == a["mechanics_step_ms"]);
  CHECK(b["steps"] == a["steps"]);
}

}  // namespace

TEST_CASE("mpirun -n 2: mechanics in series split over ranks writes one process's files") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_mechanics_in_series");
  json m = em_sheet("in_series", 40);
  m["output"]["snapshots"] = {{"every_ms", 20}, {"from_ms", 20}, {"png", true}, {"vtk", true}};
  m["output"]["vtk_format"] = "xml";
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  // The premise: the tissue contracted (|eps_yy| 1.4e-5 by 40 ms).
  const json one = summary_of(dir / "one");
  CHECK(std::abs(one["peak_strain"]["yy"].get<double>()) > 5e-6);
  const json two = summary_of(dir / "two");
  REQUIRE(two["notes"].dump().find("mechanics split over the ranks") != std::string::npos);
  check_same_bytes(dir / "one", dir / "two", 2, true);

  // Deformed particles in the frames at 20 and 40 ms (VTK XML, PNG), gathered
  // on rank 0 from every rank's bodies: every body moved as in one process
  // (its force summed over its contacts in one process's order): the same
  // bytes here.
  const std::set<std::string> frames = snapshot_names(dir / "one");
  REQUIRE(frames.size() == 5);  // two frames, each a PNG and a .vtp, and snapshots.pvd
  CHECK(snapshot_names(dir / "two") == frames);
  for (const auto& name : frames) {
    INFO(name);
    CHECK(testing::read_file(dir / "two" / name) == testing::read_file(dir / "one" / name));
  }
  CHECK(testing::read_file(dir / "one" / "snapshot_00020.000_ms.vtp") !=
        testing::read_file(dir / "one" / "snapshot_00040.000_ms.vtp"));
}

TEST_CASE("mpirun -n 2: output.reentry with mechanics, the DEM split, samples one process's fibre stretch") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_mechanics_reentry");
  // The twitch's first 40 ms sampled every 0.5 ms: V and each cell's fibre
  // stretch, which rank 0 gathers from every rank's own cells at each sample.
  json m = em_sheet("in_series", 40);
  m["output"]["reentry"] = {{"every_ms", 0.5}, {"from_ms", 0}, {"tau_ms", 1}};
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  const json one = summary_of(dir / "one"), two = summary_of(dir / "two");
  CHECK(std::abs(one["peak_strain"]["yy"].get<double>()) > 5e-6);  // the premise: the tissue contracted
  REQUIRE(two["notes"].dump().find("mechanics split over the ranks") != std::string::npos);
  check_same_bytes(dir / "one", dir / "two", 2, true);
  REQUIRE(one.contains("reentry"));
  CHECK(two["reentry"].dump() == one["reentry"].dump());
  // The tip paths' map is drawn over the last sample's fibre stretch (floats,
  // in the colour bar's 200 steps): one process's picture.
  const fs::path map = dir / "one" / "phase_singularity_paths.png";
  REQUIRE(fs::exists(map));
  CHECK(testing::read_file(dir / "two" / "phase_singularity_paths.png") == testing::read_file(map));
}

TEST_CASE("mpirun -n 2: interstitial mechanics with mechano-electric feedback split writes one process's files") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_mechanics_interstitial");
  json m = em_sheet("interstitial", 40);
  m["effects"].push_back("mechano_electric_feedback");
  // (A fibroblast: V only, no SL.)
  m["output"]["traces"].push_back({{"cells", {200}}, {"variables", {"V"}}, {"every_ms", 0.5}});
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  CHECK(std::abs(summary_of(dir / "one")["peak_strain"]["yy"].get<double>()) > 5e-6);  // 9.7e-6 by 40 ms
  check_same_bytes(dir / "one", dir / "two");
}

TEST_CASE("mpirun -n 2: mechanics with the adaptive method split agrees with one process") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_mechanics_adaptive");
  // 200 ms: through the strain's peak (near 130 ms). auto chooses the
  // adaptive method (146 cells > 16), with its implicit coupling solve.
  json m = em_sheet("in_series", 200);
  m["solver"] = {{"method", "auto"}};
  m["output"]["traces"][0]["every_ms"] = 2;
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  const json a = summary_of(dir / "one"), b = summary_of(dir / "two");
  REQUIRE(b["status"] == "completed");
  // The DEM's inputs, the cells' lengths, follow V through the Ca
  // transient; V differs from one process's by what the split CG's sums in
  // another order move it, at most its tolerance (docs/guide/parallel.md: 5e-3 mV
  // at auto's accuracy, of a 110 mV upstroke), and the strain responds to
  // the lengths smoothly. Measured: peak strain within 3.1e-7 relative
  // (xx; yy 1.4e-7), V within 1.5e-4 mV (the steps' linear forms are kept
  // in float: a difference of V's rounding can move a form by a float's
  // rounding, ~6e-8 of itself). Held to 1e-6 relative.
  // The strain is not negligible: peak eps_yy -2.53e-4, as Rush-Larsen at
  // 0.005 ms and adaptive at rtol 1e-5 give it.
  const double peak_yy = a["peak_strain"]["yy"].get<double>();
  REQUIRE(std::abs(peak_yy) > 1e-4);
  for (const char* k : {"xx", "yy", "xy"}) {
    INFO(k);
    const double pa = a["peak_strain"][k].get<double>(), pb = b["peak_strain"][k].get<double>();
    CHECK(std::abs(pb - pa) <= 1e-6 * std::abs(pa));
  }
  // Traces: the strain within 1e-5 of the peak's size, V within 0.05 mV
  // (test_mpi_tissue.cpp's kAdaptiveTraceTolerance: ten solve tolerances),
  // SL [um] within 1e-6 of its ~1.9 um. (Measured: the strain within
  // 5.4e-10, 2.1e-6 of the peak; SL within 4.9e-9 um.)
  const auto ta = csv_rows(dir / "one" / "traces.csv"), tb = csv_rows(dir / "two" / "traces.csv");
  REQUIRE(ta.size() == tb.size());
  REQUIRE(ta.size() == 102);  // the header and samples at 0, 2, ..., 200 ms
  REQUIRE(ta[0] == tb[0]);
  for (std::size_t r = 1; r < ta.size(); ++r)
    for (std::size_t c = 0; c < ta[r].size(); ++c) {
      const std::string& column = ta[0][c];
      const double tolerance = column.rfind("eps_", 0) == 0 ? 1e-5 * std::abs(peak_yy)
                               : column.rfind("V_", 0) == 0 ? 0.05
                               : column.rfind("SL_", 0) == 0 ? 1e-6 * 1.9
                                                             : 0.0;  // t_ms: the same sample times
      INFO(column, " at ", ta[r][0], " ms");
      CHECK(std::abs(number(ta[r][c]) - number(tb[r][c])) <= tolerance);
    }
  // Biomarkers: activation within 1e-3 ms (test_mpi_tissue.cpp's bounds).
  const auto ba = csv_rows(dir / "one" / "biomarkers.csv"), bb = csv_rows(dir / "two" / "biomarkers.csv");
  REQUIRE(ba.size() == bb.size());
  REQUIRE(ba.size() > 100);
  for (std::size_t r = 1; r < ba.size(); ++r) {
    CHECK(ba[r][0] == bb[r][0]);
    // (This sheet's fibroblasts, whose V stays within 0.03 mV, do not fire:
    // no activation in either run. A fired cell whose APD90 the run did not
    // reach, nan, is compared still.)
    CHECK(ba[r][3].empty() == bb[r][3].empty());
    if (ba[r][3].empty()) continue;
    CHECK(std::abs(number(ba[r][3]) - number(bb[r][3])) <= 1e-3);
  }
}

TEST_CASE("mpirun -n 2: an EM run split, killed and resumed on 2 ranks or in one process writes the run never stopped") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_mechanics_checkpoints");
  // 40 ms of rush_larsen at 0.01 ms: 4000 steps, checkpoints at 10, 20, 30 ms.
  json m = em_sheet("interstitial", 40);
  m["output"]["checkpoint"] = {{"every_ms", 10}, {"keep", 1}};
  std::ofstream(dir / "scene.json") << m.dump();
  const std::string two = testing::mpirun(2);
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(two, dir / "scene.json", dir / "reference") == 0);
  check_same_bytes(dir / "one", dir / "reference");

  // Killed at step 3500, after the checkpoint at 30 ms; resumed from it.
  REQUIRE(testing::run_scene("FIBRODEM_TEST_KILL=step:3500 " + two, dir / "scene.json", dir / "killed") != 0);
  REQUIRE(summary_of(dir / "killed")["status"] == "running");
  CHECK(fs::exists(dir / "killed" / "checkpoints" / "t_000000030000us.rank1.ckpt"));
  // The same checkpoint resumed in one process (its parts cut again: the
  // myofilaments' and the DEM's states, rank 0's, with the cells').
  fs::copy(dir / "killed", dir / "killed_one", fs::copy_options::recursive);
  REQUIRE(testing::run_fibrodem(two, "resume --quiet --no-report " + (dir / "killed").string(),
                                dir / "resume.txt") == 0);
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"] == 30);
  check_same_bytes(dir / "reference", dir / "killed");
  REQUIRE(testing::run_fibrodem("", "resume --quiet --no-report " + (dir / "killed_one").string(),
                                dir / "resume_one.txt") == 0);
  check_same_bytes(dir / "reference", dir / "killed_one", 1);
}

// (Labelled slow: the split DEM's checkpoint and resume run under the
// sanitizers in the EM case above and in tests/mechanics/test_dem_split.cpp;
// this one adds a DEM awake at the checkpoint and other rank counts.)
TEST_CASE(
    "mpirun -n 2: the DEM split over ranks, killed and resumed on 2, 3 or 1 ranks, writes the run never stopped" *
    doctest::test_suite("mpi slow")) {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_dem_split_checkpoints");
  // 80 ms of rush_larsen at 0.01 ms: the DEM, split, takes ~200 steps from
  // ~50 ms on (its tissue at rest before); checkpoints at 20, 40, 60 ms.
  json m = em_sheet("in_series", 80);
  m["output"]["checkpoint"] = {{"every_ms", 20}, {"keep", 1}};
  std::ofstream(dir / "scene.json") << m.dump();
  const std::string two = testing::mpirun(2);
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(two, dir / "scene.json", dir / "reference") == 0);
  REQUIRE(summary_of(dir / "reference")["notes"].dump().find("mechanics split over the ranks") != std::string::npos);
  check_same_bytes(dir / "one", dir / "reference", 2, true);
  // Killed at step 7000, after the checkpoint at 60 ms, with the DEM awake.
  REQUIRE(testing::run_scene("FIBRODEM_TEST_KILL=step:7000 " + two, dir / "scene.json", dir / "killed") != 0);
  for (const char* copy : {"killed_one", "killed_three"})
    fs::copy(dir / "killed", dir / copy, fs::copy_options::recursive);
  // Resumed on 2 ranks: the same bytes as the run never stopped (every
  // rank takes the whole tissue's DEM from the checkpoint, which rank 0
  // wrote as one process writes it); on 1 and 3, the strain to rounding.
  REQUIRE(testing::run_fibrodem(two, "resume --quiet --no-report " + (dir / "killed").string(), dir / "r2.txt") == 0);
  CHECK(summary_of(dir / "killed")["resumed_from"]["time_ms"] == 60);
  check_same_bytes(dir / "reference", dir / "killed");
  REQUIRE(testing::run_fibrodem("", "resume --quiet --no-report " + (dir / "killed_one").string(),
                                dir / "r1.txt") == 0);
  check_same_bytes(dir / "reference", dir / "killed_one", 1, true);
  REQUIRE(testing::run_fibrodem(testing::mpirun(3), "resume --quiet --no-report " + (dir / "killed_three").string(),
                                dir / "r3.txt") == 0);
  check_same_bytes(dir / "reference", dir / "killed_three", 3, true);
}

TEST_CASE("mpirun -n 2: the tissue's stretch feeding the cells, with the DEM split, agrees with one process") {
  FIBRODEM_SKIP_WITHOUT_MPIRUN();
  const auto dir = testing::scratch_dir("mpi_dem_split_tissue_stretch");
  // Each rank measures its own cells' fibre stretch from its own and its
  // ghost bodies (mechano_electric_feedback.stretch "tissue"); the DEM's
  // rounding (its strain within 1e-16 of its peak, above) reaches V
  // through the stretch-activated current: V within 1e-6 mV, SL within
  // 1e-9 um, the strain within 1e-12 of its peak (measured below).
  json m = em_sheet("in_series", 80);
  m["effects"].push_back("mechano_electric_feedback");
  m["mechano_electric_feedback"] = {{"stretch", "tissue"}};
  std::ofstream(dir / "scene.json") << m.dump();
  REQUIRE(testing::run_scene("", dir / "scene.json", dir / "one") == 0);
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "scene.json", dir / "two") == 0);
  REQUIRE(summary_of(dir / "two")["notes"].dump().find("mechanics split over the ranks") != std::string::npos);
  const auto ta = csv_rows(dir / "one" / "traces.csv"), tb = csv_rows(dir / "two" / "traces.csv");
  REQUIRE(ta.size() == tb.size());
  REQUIRE(ta[0] == tb[0]);
  const double peak_yy = summary_of(dir / "one")["peak_strain"]["yy"].get<double>();
  CHECK(std::abs(peak_yy) > 1e-4);  // (1.6e-4: the DEM did move)
  double largest[3] = {0, 0, 0};  // strain, V, SL
  for (std::size_t r = 1; r < ta.size(); ++r)
    for (std::size_t c = 1; c < ta[r].size(); ++c) {
      const int kind = ta[0][c].rfind("eps_", 0) == 0 ? 0 : ta[0][c].rfind("V_", 0) == 0 ? 1 : 2;
      largest[kind] = std::max(largest[kind], std::abs(number(ta[r][c]) - number(tb[r][c])));
    }
  MESSAGE("two ranks against one process: strain within ", largest[0], ", V within ", largest[1], " mV, SL within ",
          largest[2], " um");
  CHECK(largest[0] <= 1e-12 * std::abs(peak_yy));
  CHECK(largest[1] <= 1e-6);
  CHECK(largest[2] <= 1e-9);

  // With the DEM kept on rank 0 (multirate), the tissue's stretch is refused over ranks, naming why.
  m["mechanics"]["multirate"] = true;
  std::ofstream(dir / "multirate.json") << m.dump();
  REQUIRE(testing::run_scene(testing::mpirun(2), dir / "multirate.json", dir / "refused") != 0);
  const std::string said = testing::read_file(dir / "refused.txt");
  CHECK(said.find("mechano_electric_feedback.stretch") != std::string::npos);
  CHECK(said.find("mechanics.multirate") != std::string::npos);
}

TEST_SUITE_END();
