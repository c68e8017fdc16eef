// output.reentry's frames kept on disk beside a run's checkpoints, so that
// a resumed run measures re-entry over the whole record, as the run that
// never stopped does (its phase singularities, tracks, dominant frequency
// and activations start at from_ms, not at the resume).
//
// At each checkpoint the frames taken since the last one are appended to
// checkpoints/<name>.frames and flushed to disk before the checkpoint is
// written; the checkpoint records how many frames the log held. A resumed
// run reads that many back and cuts whatever a later, lost checkpoint had
// appended. The file: the 8 bytes "FDFRAME1", the cell count (uint64), then
// per frame its time [ms] (float64) and one float32 a cell, in the host's
// byte order (a checkpoint is read back by the build that wrote it).
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "measure/cell_frames.hpp"

namespace fibrodem {

class FrameLog {
 public:
  // The log at `file`; nothing is opened until the first append.
  explicit FrameLog(std::filesystem::path file) : file_(std::move(file)) {}

  // A resumed run whose log this is: its first `frames` frames (of `cells`
  // values) are the checkpoint's, read back; what follows them is cut, and
  // appends go on from there. Throws CheckpointError naming the file if it
  // cannot be cut.
  void continue_after(std::size_t frames, std::size_t cells);
  // Appends frames [written(), frames.count()) of `frames` and flushes them
  // to the disk (fsync). Until continue_after or a first append, the file
  // is started afresh. Throws std::runtime_error naming the file if it
  // cannot be written.
  void append_new(const CellFrames& frames);
  // The frames on disk.
  std::size_t written() const { return written_; }
  const std::filesystem::path& file() const { return file_; }

 private:
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::filesystem::path file_;
  std::unique_ptr<std::FILE, Close> out_;
  std::size_t written_ = 0;
  bool continues_ = false;
};

// Reads the first `count` frames of the log `file` into `frames` (empty,
// its cell count set; room for them made by the caller). Throws
// CheckpointError (io/checkpoint_file.hpp) naming the file if it is
// missing, holds another cell count, or fewer frames.
void read_frame_log(const std::filesystem::path& file, std::size_t count, CellFrames& frames);

}  // namespace fibrodem
