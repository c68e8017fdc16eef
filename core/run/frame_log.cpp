#include "run/frame_log.hpp"

#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

#include "io/checkpoint_file.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

namespace {

constexpr std::array<char, 8> kMagic{'F', 'D', 'F', 'R', 'A', 'M', 'E', '1'};
constexpr std::size_t kHeaderBytes = kMagic.size() + sizeof(std::uint64_t);

std::size_t frame_bytes(std::size_t cells) { return sizeof(double) + cells * sizeof(float); }

[[noreturn]] void cannot_write(const fs::path& file, const std::string& why) {
  throw std::runtime_error("cannot write the re-entry frames to " + file.string() + ": " + why);
}

}  // namespace

void FrameLog::continue_after(std::size_t frames, std::size_t cells) {
  std::error_code ec;
  fs::resize_file(file_, kHeaderBytes + frames * frame_bytes(cells), ec);
  if (ec) throw CheckpointError("cannot cut " + file_.string() + " to the checkpoint's frames: " + ec.message());
  out_.reset();
  written_ = frames;
  continues_ = true;
}

void FrameLog::append_new(const CellFrames& frames) {
  if (!out_) {
    out_.reset(std::fopen(file_.c_str(), continues_ ? "ab" : "wb"));
    if (!out_) cannot_write(file_, std::strerror(errno));
    if (!continues_) {
      const auto cells = static_cast<std::uint64_t>(frames.cells);
      if (std::fwrite(kMagic.data(), 1, kMagic.size(), out_.get()) != kMagic.size() ||
          std::fwrite(&cells, sizeof cells, 1, out_.get()) != 1)
        cannot_write(file_, "write failed (is the disk full?)");
    }
  }
  for (; written_ < frames.count(); ++written_) {
    if (std::fwrite(&frames.t_ms[written_], sizeof(double), 1, out_.get()) != 1 ||
        std::fwrite(frames.frame(written_), sizeof(float), frames.cells, out_.get()) != frames.cells)
      cannot_write(file_, "write failed (is the disk full?)");
  }
  if (std::fflush(out_.get()) != 0 || ::fsync(::fileno(out_.get())) != 0) cannot_write(file_, "flush failed");
}

void read_frame_log(const fs::path& file, std::size_t count, CellFrames& frames) {
  using Closed = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;
  const Closed in(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!in) throw CheckpointError("the re-entry frames it counts, " + file.string() + ", cannot be read");
  std::array<char, 8> magic{};
  std::uint64_t cells = 0;
  if (std::fread(magic.data(), 1, magic.size(), in.get()) != magic.size() || magic != kMagic ||
      std::fread(&cells, sizeof cells, 1, in.get()) != 1)
    throw CheckpointError(file.string() + " is not a file of re-entry frames");
  if (cells != frames.cells)
    throw CheckpointError(file.string() + " holds frames of " + std::to_string(cells) + " cells, this run has " +
                          std::to_string(frames.cells));
  frames.t_ms.resize(count);
  frames.values.resize(count * frames.cells);
  for (std::size_t k = 0; k < count; ++k)
    if (std::fread(&frames.t_ms[k], sizeof(double), 1, in.get()) != 1 ||
        std::fread(&frames.values[k * frames.cells], sizeof(float), frames.cells, in.get()) != frames.cells)
      throw CheckpointError(file.string() + " holds fewer than the " + std::to_string(count) +
                            " re-entry frames its checkpoint counts");
}

}  // namespace fibrodem
