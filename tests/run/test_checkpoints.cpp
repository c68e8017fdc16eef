// Checkpoints and resume, and starting a scene
// from another run's state: a run killed with SIGKILL at any moment
// and resumed with `fibrodem resume` writes the same bytes to traces.csv and
// biomarkers.csv as a run never stopped.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <regex>

#include "io/checkpoint_file.hpp"
#include "run/checkpoint_dir.hpp"
#include "util/manifest_error.hpp"
#include "util/sha256.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

namespace {

const std::string kFibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem";

// The exit code of a shell command (128 + n if it died of signal n).
int shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// `fibrodem run` of manifest m into out; `kill` is FIBRODEM_TEST_KILL (step:N
// or checkpoint:K: SIGKILL at that step, or halfway through writing that
// checkpoint), empty for none.
int run(const json& m, const fs::path& out, const std::string& kill = "") {
  const fs::path manifest = out.string() + ".json";
  std::ofstream(manifest) << m.dump();
  return shell((kill.empty() ? "" : "FIBRODEM_TEST_KILL=" + kill + " ") + kFibrodem + " run --quiet " +
               manifest.string() + " --out " + out.string() + " > /dev/null 2>&1");
}

// `fibrodem resume out`, its standard error kept in out.err.
int resume(const fs::path& out) {
  return shell(kFibrodem + " resume --quiet " + out.string() + " > /dev/null 2> " + out.string() + ".err");
}

json summary_of(const fs::path& dir) { return json::parse(testing::read_file(dir / "summary.json")); }

void check_same_outputs_but_reentry(const fs::path& reference, const fs::path& resumed) {
  const std::string traces = testing::read_file(reference / "traces.csv");
  REQUIRE(traces.size() > 100);
  CHECK(testing::read_file(resumed / "traces.csv") == traces);
  CHECK(testing::read_file(resumed / "biomarkers.csv") == testing::read_file(reference / "biomarkers.csv"));
  const json a = summary_of(reference), b = summary_of(resumed);
  CHECK(b["status"] == "completed");
  CHECK(b["steps"] == a["steps"]);
  CHECK(b["mean_biomarkers"] == a["mean_biomarkers"]);
  CHECK(b["peak_strain"] == a["peak_strain"]);
}

void check_same_outputs(const fs::path& reference, const fs::path& resumed) {
  check_same_outputs_but_reentry(reference, resumed);
  // output.reentry measured over the whole record: its frames before the
  // checkpoint come back from the logs beside it (run/frame_log.hpp).
  const json a = summary_of(reference), b = summary_of(resumed);
  CHECK(b.value("reentry", json()).dump() == a.value("reentry", json()).dump());
  for (const char* name : {"phase_singularities.csv", "phase_singularity_tracks.csv"})
    if (fs::exists(reference / name)) CHECK(testing::read_file(resumed / name) == testing::read_file(reference / name));
}

// Runs m once whole (the reference), then killed at several moments (a
// fraction of the reference's steps: before the first checkpoint, within
// segments, late; and halfway through writing the second checkpoint), each
// resumed: the same outputs every time.
void check_kill_and_resume(const std::string& name, json m) {
  const auto dir = testing::scratch_dir("checkpoints_" + name);
  REQUIRE(run(m, dir / "reference") == 0);
  const long long steps = summary_of(dir / "reference")["steps"].get<long long>();
  std::vector<std::string> kills = {"checkpoint:2"};
  for (double fraction : {0.1, 0.5, 0.85}) kills.push_back("step:" + std::to_string(static_cast<long long>(fraction * steps)));
  int from_checkpoint = 0;  // resumes that started from a checkpoint, not from t = 0
  for (std::size_t i = 0; i < kills.size(); ++i) {
    const std::string kill = kills[i];
    CAPTURE(kill);
    const fs::path out = dir / ("killed_" + std::to_string(i));
    REQUIRE(run(m, out, kill) == 128 + 9);
    CHECK(summary_of(out)["status"] == "running");  // what a killed run leaves
    REQUIRE(resume(out) == 0);
    check_same_outputs(dir / "reference", out);
    const json resumed_from = summary_of(out)["resumed_from"];
    if (!resumed_from.is_null() && resumed_from["time_ms"].get<double>() > 0) ++from_checkpoint;
  }
  CHECK(from_checkpoint >= 2);  // (CVODE spends most steps on the upstroke, before the first checkpoint)
}

// A strand of 12 colman myocytes, paced at one end, checkpointed every 50 ms.
json strand(const json& solver) {
  json m = json::parse(R"({
    "fibrodem": 1, "name": "strand", "duration_ms": 300,
    "tissue": {"builder": "strand", "type": "myocyte", "cells": 12},
    "cells": {"myocyte": {"model": "colman"}},
    "coupling": {"D_m_nS": 1000},
    "stimulus": [{"target": [0, 1], "start_ms": 10, "duration_ms": 2, "amplitude_pA": 4000}],
    "output": {"traces": {"cells": [0, 6, 11], "variables": ["V", "Ca_i"], "every_ms": 0.5},
               "checkpoint": {"every_ms": 50}}
  })");
  m["solver"] = solver;
  return m;
}

json example(const std::string& name) {
  return json::parse(testing::read_file(fs::path(FIBRODEM_SOURCE_DIR) / "examples" / name));
}

}  // namespace

TEST_CASE("a checkpoint file reads back its fields, a truncated, corrupt or foreign file is named as such") {
  CheckpointFields f;
  f.put("a.numbers", std::vector<double>{1.5, -2.25, 1e-300});
  f.put_integer("a.count", 42);
  f.put_text("a.text", "colman");
  const std::string bytes = f.encode();
  const CheckpointFields back = CheckpointFields::decode(bytes);
  CHECK(back.numbers("a.numbers") == std::vector<double>{1.5, -2.25, 1e-300});
  CHECK(back.integer("a.count") == 42);
  CHECK(back.text("a.text") == "colman");
  CHECK_THROWS_WITH_AS(back.numbers("a.numbers", 4), doctest::Contains("'a.numbers' has 3 values, the scene needs 4"),
                       CheckpointError);
  CHECK_THROWS_WITH_AS(back.number("a.missing"), doctest::Contains("no field 'a.missing'"), CheckpointError);
  CHECK_THROWS_WITH_AS(back.numbers("a.count"), doctest::Contains("holds integers, expected numbers"), CheckpointError);

  CHECK_THROWS_WITH_AS(CheckpointFields::decode(bytes.substr(0, bytes.size() - 1)), doctest::Contains("truncated"),
                       CheckpointError);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  CHECK_THROWS_WITH_AS(CheckpointFields::decode(flipped), doctest::Contains("checksum does not match"),
                       CheckpointError);
  CHECK_THROWS_WITH_AS(CheckpointFields::decode(std::string(100, 'x')), doctest::Contains("not a fibrodem checkpoint"),
                       CheckpointError);
  const auto dir = testing::scratch_dir("checkpoint_file");
  write_checkpoint_file(dir / "c.ckpt", f);
  CHECK(read_checkpoint_file(dir / "c.ckpt").text("a.text") == "colman");
  // Streamed to the file piece by piece, it is the encoding, its checksum
  // the SHA-256 of all before it.
  CHECK(testing::read_file(dir / "c.ckpt") == bytes);
  CHECK(f.encoded_size() == bytes.size());
  const auto digest = sha256(std::string_view(bytes).substr(0, bytes.size() - 32));
  CHECK(bytes.substr(bytes.size() - 32) == std::string(digest.begin(), digest.end()));
  // Read from the file as it is parsed, a damaged file gives decode()'s
  // error: every byte flipped in turn (the header, each field's name,
  // kind, length and data, the checksum), the file cut at every length, and
  // a payload that does not parse under a checksum that matches it.
  const auto error_of = [](const std::function<void()>& read) {
    try {
      read();
    } catch (const CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  const auto file_error = [&](const std::string& content) {
    std::ofstream(dir / "d.ckpt", std::ios::binary) << content;
    const std::string e = error_of([&] { read_checkpoint_file(dir / "d.ckpt"); });
    const std::string prefix = "checkpoint " + (dir / "d.ckpt").string() + ": ";
    return e.rfind(prefix, 0) == 0 ? e.substr(prefix.size()) : e;
  };
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    CAPTURE(k);
    std::string damaged = bytes;
    damaged[k] ^= 0x40;
    const std::string expected = error_of([&] { CheckpointFields::decode(damaged); });
    CHECK(expected != "read");
    CHECK(file_error(damaged) == expected);
    CHECK(file_error(bytes.substr(0, k)) == error_of([&] { CheckpointFields::decode(bytes.substr(0, k)); }));
  }
  std::string unparsed = bytes;
  unparsed[32] ^= 0x01;  // the payload's field count (after the 32-byte header)
  const auto resealed = sha256(std::string_view(unparsed).substr(0, unparsed.size() - 32));
  unparsed.replace(unparsed.size() - 32, 32, std::string(resealed.begin(), resealed.end()));
  const std::string unparsed_error = error_of([&] { CheckpointFields::decode(unparsed); });
  CHECK(unparsed_error.find("checksum") == std::string::npos);
  CHECK(unparsed_error != "read");
  CHECK(file_error(unparsed) == unparsed_error);
  // A test's hook runs once, when half the file is on disk.
  std::uintmax_t at_midway = 0;
  int calls = 0;
  write_checkpoint_file(dir / "d.ckpt", f, [&] {
    at_midway = fs::file_size(dir / "d.ckpt.tmp");
    ++calls;
  });
  CHECK(calls == 1);
  CHECK(at_midway == bytes.size() / 2);
  CHECK_FALSE(fs::exists(dir / "c.ckpt.tmp"));
  CHECK_THROWS_WITH_AS(read_checkpoint_file(dir / "none.ckpt"), doctest::Contains("none.ckpt cannot be read"),
                       CheckpointError);
}

TEST_CASE("killed (SIGKILL) at any step and resumed, a run writes the same traces and biomarkers as one never stopped" * doctest::test_suite("slow threads")) {
  SUBCASE("forward Euler") { check_kill_and_resume("euler", strand({{"method", "euler"}, {"dt_ms", 0.005}})); }
  SUBCASE("Rush-Larsen with output.reentry") {
    // The wave's activations (from 10 ms) fall before most kills' checkpoints.
    json m = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
    m["output"]["reentry"] = {{"every_ms", 1}, {"tau_ms", 5}};
    check_kill_and_resume("rush_larsen", m);
  }
  SUBCASE("second-order Rush-Larsen") {
    check_kill_and_resume("rush_larsen2", strand({{"method", "rush_larsen2"}, {"dt_ms", 0.01}}));
  }
  SUBCASE("adaptive") { check_kill_and_resume("adaptive", strand({{"method", "adaptive"}})); }
  SUBCASE("CVODE") {
    check_kill_and_resume("cvode", strand({{"method", "cvode"}, {"rtol", 1e-6}, {"atol", 1e-8}}));
  }
  SUBCASE("pre-upstroke RMP and transit CV (the window of V is in the checkpoint), brocklehurst2022_tissue") {
    json m = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
    m["cells"]["myocyte"]["variant"] = "brocklehurst2022_tissue";
    m["duration_ms"] = 450;
    m["stimulus"][0]["period_ms"] = 250;  // a second beat after the checkpoints at 50 ... 250 ms
    m["stimulus"][0]["count"] = 2;
    m["output"]["biomarkers"] = {{"rmp", "pre_upstroke"}, {"cv", "transit"}};
    check_kill_and_resume("pre_upstroke", m);
  }
  SUBCASE("electrophysiology and contraction (colman + rice, two beats)") {
    json m = example("single_cell_em.json");
    m["duration_ms"] = 1300;
    m["output"]["checkpoint"] = {{"every_ms", 100}};
    check_kill_and_resume("contraction", m);
  }
  SUBCASE("DEM mechanics (a piece of the Fig. 3 in-series tissue, snapshots on)") {
    json m = example("fig3_in_series_em.json");
    m["duration_ms"] = 200;
    m["tissue"]["width_mm"] = 0.3;
    m["tissue"]["height_mm"] = 0.8;
    m["stimulus"][0]["start_ms"] = 20;
    m["output"]["checkpoint"] = {{"every_ms", 50}};
    // The fibre stretch is sampled with V (its frames' log beside V's):
    // frames of the one at other times than the other's fail the measure.
    m["output"]["reentry"] = {{"every_ms", 2}, {"tau_ms", 10}};
    check_kill_and_resume("dem", m);
  }
}

TEST_CASE("killed at a random moment of wall time, a resumed run still writes the same outputs") {
  const auto dir = testing::scratch_dir("checkpoints_timed_kill");
  json m = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
  m["duration_ms"] = 1000;
  m["output"]["checkpoint"]["every_ms"] = 20;
  REQUIRE(run(m, dir / "reference") == 0);
  std::ofstream(dir / "m.json") << m.dump();
  for (const char* after_s : {"0.05", "0.2", "0.4"}) {
    CAPTURE(after_s);
    const fs::path out = dir / (std::string("killed_after_") + after_s);
    const int code = shell("timeout -s KILL " + std::string(after_s) + " " + kFibrodem + " run --quiet " +
                           (dir / "m.json").string() + " --out " + out.string() + " > /dev/null 2>&1");
    if (code == 0) continue;  // the run was done before the kill: nothing to resume
    REQUIRE(code == 128 + 9);
    if (!fs::exists(out / "summary.json")) continue;  // killed before it had set up: nothing was written
    // Killed after the run had completed (while writing report.html, after
    // summary.json): the outputs are whole and there is nothing to resume.
    if (summary_of(out).value("status", "") != "completed") REQUIRE(resume(out) == 0);
    check_same_outputs(dir / "reference", out);
  }
}

TEST_CASE("a truncated or corrupt checkpoint is named and the one before it used") {
  const auto dir = testing::scratch_dir("checkpoints_corrupt");
  json m = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
  m["output"]["checkpoint"]["keep"] = 3;
  REQUIRE(run(m, dir / "reference") == 0);
  const fs::path out = dir / "killed";
  REQUIRE(run(m, out, "step:" + std::to_string(27000)) == 128 + 9);  // after the checkpoint at 250 ms
  const auto files = list_checkpoints(out);
  REQUIRE(files.size() == 3);  // 250, 200, 150 ms
  fs::resize_file(files[0], fs::file_size(files[0]) / 2);
  {
    std::fstream f(files[1], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(files[1]) / 2));
    f.put('\x7f');
  }
  REQUIRE(resume(out) == 0);
  const std::string err = testing::read_file(out.string() + ".err");
  CHECK(err.find(files[0].filename().string() + ": it is truncated") != std::string::npos);
  CHECK(err.find(files[1].filename().string() + ": its checksum does not match") != std::string::npos);
  CHECK(err.find("from " + files[2].string()) != std::string::npos);
  check_same_outputs(dir / "reference", out);
  CHECK(summary_of(out)["resumed_from"]["time_ms"] == 150.0);
}

TEST_CASE("without the re-entry frames its checkpoint counts, a resumed run says so and measures from the resume") {
  const auto dir = testing::scratch_dir("checkpoints_frames_lost");
  json m = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
  m["output"]["reentry"] = {{"every_ms", 1}, {"tau_ms", 5}};
  REQUIRE(run(m, dir / "reference") == 0);
  // The log holds every sample (8 bytes of time, 4 a cell) after 16 bytes
  // of header, as the run's estimate of its outputs says (run.log).
  const double log_bytes = static_cast<double>(fs::file_size(dir / "reference" / "checkpoints" / "reentry_V.frames"));
  CHECK(log_bytes == 16 + 301 * (8 + 12 * 4));
  std::smatch said;
  const std::string log = testing::read_file(dir / "reference" / "run.log");
  REQUIRE(std::regex_search(log, said, std::regex(R"(re-entry samples beside the checkpoints: 301 ([0-9.]+) kB)")));
  CHECK(std::stod(said[1]) * 1e3 == doctest::Approx(log_bytes).epsilon(0.01));
  const fs::path out = dir / "killed";
  REQUIRE(run(m, out, "step:" + std::to_string(27000)) == 128 + 9);  // after the checkpoint at 250 ms
  REQUIRE(fs::remove(out / "checkpoints" / "reentry_V.frames"));
  REQUIRE(resume(out) == 0);
  CHECK(summary_of(out)["status"] == "completed");
  CHECK(testing::read_file(out / "run.log").find("reentry_V.frames, cannot be read; re-entry is measured from t = 250 ms") !=
        std::string::npos);
  // Measured from 250 ms: the first 250 samples (the wave at 10 ms among
  // them) are not in it.
  CHECK(summary_of(out)["reentry"]["samples"].get<int>() == summary_of(dir / "reference")["reentry"]["samples"].get<int>() - 250);
  check_same_outputs_but_reentry(dir / "reference", out);
}

TEST_CASE("resume refuses a folder without a run, and a run that completed") {
  const auto dir = testing::scratch_dir("checkpoints_refusals");
  fs::create_directories(dir / "empty");
  CHECK(resume(dir / "empty") == 2);
  CHECK(testing::read_file((dir / "empty").string() + ".err").find("holds no run to resume") != std::string::npos);
  REQUIRE(run(strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}}), dir / "done") == 0);
  CHECK(resume(dir / "done") == 2);
  CHECK(testing::read_file((dir / "done").string() + ".err").find("completed: nothing to resume") != std::string::npos);
}

TEST_CASE("initial_state starts a scene from another run's checkpoint, another tissue or model is refused, naming it") {
  const auto dir = testing::scratch_dir("initial_state");
  json paced = strand({{"method", "rush_larsen"}, {"dt_ms", 0.01}});
  REQUIRE(run(paced, dir / "paced") == 0);  // checkpoints at 250 and 300 ms (the newest two)

  json branch = paced;
  branch["duration_ms"] = 5;
  branch["stimulus"] = json::array();
  branch["output"].erase("checkpoint");
  branch["initial_state"] = {{"from", (dir / "paced").string()}, {"time_ms", 300}};
  REQUIRE(run(branch, dir / "branch") == 0);
  // The branch's first sample (t = 0) is the paced run's last (t = 300 ms), to the bit.
  auto row = [](const std::string& csv, bool last) {
    const std::string body = csv.substr(0, csv.size() - 1);
    const auto line = last ? body.substr(body.rfind('\n') + 1) : body.substr(body.find('\n') + 1, body.find('\n', body.find('\n') + 1) - body.find('\n') - 1);
    return line.substr(line.find(','));  // without the time
  };
  CHECK(row(testing::read_file(dir / "branch" / "traces.csv"), false) ==
        row(testing::read_file(dir / "paced" / "traces.csv"), true));
  CHECK(summary_of(dir / "branch")["notes"].dump().find("initial_state: the cells' states of") != std::string::npos);

  auto refused = [&](json m) {
    try {
      Scene scene = parse_scene(m);
      Simulation sim(scene);
    } catch (const ManifestError& e) {
      CHECK(std::string(e.what()).find("initial_state") != std::string::npos);
      return std::string(e.what());
    }
    FAIL("accepted");
    return std::string();
  };
  json other_tissue = branch;
  other_tissue["tissue"]["cells"] = 13;
  CHECK(refused(other_tissue).find("its tissue has 12 cells, this scene's has 13") != std::string::npos);
  json other_model = branch;
  other_model["cells"]["myocyte"]["model"] = "courtemanche";
  CHECK(refused(other_model).find("its ionic.myocyte.model is colman, this scene's is courtemanche") != std::string::npos);
  json other_time = branch;
  other_time["initial_state"]["time_ms"] = 123;
  CHECK(refused(other_time).find("no checkpoint at t = 123 ms; it has 250, 300 ms") != std::string::npos);
  json nothing = branch;
  nothing["initial_state"]["from"] = (dir / "nowhere").string();
  CHECK(refused(nothing).find("neither a checkpoint file nor a run's folder") != std::string::npos);
}
