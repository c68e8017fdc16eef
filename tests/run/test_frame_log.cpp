// The re-entry frames kept beside a run's checkpoints (run/frame_log.hpp):
// appended at each checkpoint, read back on resume, cut after the frames the
// checkpoint counts; a missing, foreign or short log is named.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "io/checkpoint_file.hpp"
#include "run/frame_log.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;
namespace fs = std::filesystem;

namespace {

// Frame k of 3 cells: V = -80 + 10 k + c (c the cell), at t = 2 k ms.
CellFrames frames_up_to(int count) {
  CellFrames frames(3);
  for (int k = 0; k < count; ++k) frames.add(2.0 * k, {-80.0 + 10 * k, -79.0 + 10 * k, -78.0 + 10 * k});
  return frames;
}

}  // namespace

TEST_CASE("frame log: frames appended at checkpoints read back, what a lost checkpoint appended is cut") {
  const auto dir = testing::scratch_dir("frame_log");
  const fs::path file = dir / "reentry_V.frames";
  {
    FrameLog log(file);
    CellFrames held = frames_up_to(2);
    log.append_new(held);  // checkpoint 1: 2 frames
    CHECK(log.written() == 2);
    held = frames_up_to(5);
    log.append_new(held);  // checkpoint 2: 3 more, then the run is killed
    CHECK(log.written() == 5);
  }
  // 8 bytes of name, the cell count, then 8 + 3 x 4 bytes a frame.
  CHECK(fs::file_size(file) == 16 + 5 * 20);

  // Resumed from checkpoint 1 (its count: 2 frames).
  CellFrames back(3);
  read_frame_log(file, 2, back);
  CHECK(back.t_ms == std::vector<double>{0, 2});
  CHECK(back.values == frames_up_to(2).values);
  FrameLog log(file);
  log.continue_after(2, 3);
  CHECK(fs::file_size(file) == 16 + 2 * 20);
  back.add(4, {1, 2, 3});
  log.append_new(back);  // the resumed run's next checkpoint: one frame more
  CHECK(log.written() == 3);
  CellFrames again(3);
  read_frame_log(file, 3, again);
  CHECK(again.t_ms == std::vector<double>{0, 2, 4});
  CHECK(again.values.back() == 3.0f);

  // A new run's log starts afresh.
  FrameLog fresh(file);
  fresh.append_new(frames_up_to(1));
  CHECK(fs::file_size(file) == 16 + 20);
}

TEST_CASE("frame log: a missing, foreign or short log, or one of another tissue, is named") {
  const auto dir = testing::scratch_dir("frame_log_errors");
  CellFrames frames(3);
  CHECK_THROWS_WITH_AS(read_frame_log(dir / "none.frames", 1, frames), doctest::Contains("none.frames, cannot be read"),
                       CheckpointError);
  std::ofstream(dir / "foreign.frames") << "not frames at all";
  CHECK_THROWS_WITH_AS(read_frame_log(dir / "foreign.frames", 1, frames),
                       doctest::Contains("foreign.frames is not a file of re-entry frames"), CheckpointError);
  FrameLog(dir / "short.frames").append_new(frames_up_to(2));
  CHECK_THROWS_WITH_AS(read_frame_log(dir / "short.frames", 3, frames),
                       doctest::Contains("fewer than the 3 re-entry frames its checkpoint counts"), CheckpointError);
  CellFrames other(4);
  CHECK_THROWS_WITH_AS(read_frame_log(dir / "short.frames", 1, other),
                       doctest::Contains("holds frames of 3 cells, this run has 4"), CheckpointError);
  CHECK_THROWS_WITH_AS(FrameLog(dir / "no_such_folder" / "x.frames").append_new(frames_up_to(1)),
                       doctest::Contains("cannot write the re-entry frames to"), std::runtime_error);
}
