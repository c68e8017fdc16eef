#include "run/checkpoint_dir.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace fibrodem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFolder = "checkpoints";
constexpr const char* kSuffix = ".ckpt";

// The time in a checkpoint's name [us], or -1 if the name is not one.
long long time_in_name(const fs::path& file) {
  const std::string name = file.filename().string();
  const std::string tail = std::string("us") + kSuffix;
  if (name.size() <= 2 + tail.size() || name.rfind("t_", 0) != 0 ||
      name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
    return -1;
  const std::string digits = name.substr(2, name.size() - 2 - tail.size());
  if (digits.empty() || digits.size() > 15 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return -1;
  return std::stoll(digits);
}

}  // namespace

fs::path checkpoint_path(const fs::path& run_dir, double t_ms) {
  return run_dir / kFolder / fmt::format("t_{:012d}us{}", std::llround(t_ms * 1000.0), kSuffix);
}

fs::path rank_checkpoint_path(const fs::path& checkpoint, int rank) {
  return checkpoint.parent_path() / (checkpoint.stem().string() + ".rank" + std::to_string(rank) + kSuffix);
}

std::vector<fs::path> list_checkpoints(const fs::path& run_dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(run_dir / kFolder, ec))
    if (time_in_name(entry.path()) >= 0) files.push_back(entry.path());
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return time_in_name(a) > time_in_name(b); });
  return files;
}

void prune_checkpoints(const fs::path& run_dir, int keep) {
  // A temporary file left by a run killed while writing one goes too.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(run_dir / kFolder, ec))
    if (entry.path().extension() == ".tmp") fs::remove(entry.path(), ec);
  const auto files = list_checkpoints(run_dir);
  std::vector<std::string> removed;  // their stems, t_<time>us
  for (std::size_t i = static_cast<std::size_t>(std::max(keep, 1)); i < files.size(); ++i) {
    fs::remove(files[i]);
    removed.push_back(files[i].stem().string() + ".rank");
  }
  if (removed.empty()) return;
  for (const auto& entry : fs::directory_iterator(run_dir / kFolder, ec)) {
    const std::string name = entry.path().filename().string();
    for (const auto& stem : removed)
      if (name.rfind(stem, 0) == 0) fs::remove(entry.path(), ec);
  }
}

void clear_checkpoints(const fs::path& run_dir) {
  std::error_code ec;
  fs::remove_all(run_dir / kFolder, ec);
}

CheckpointSearch latest_good_checkpoint(const fs::path& run_dir) {
  CheckpointSearch search;
  for (const auto& file : list_checkpoints(run_dir)) {
    try {
      search.found = FoundCheckpoint{file, read_checkpoint_file(file), search.skipped};
      break;
    } catch (const CheckpointError& e) {
      search.skipped.push_back(e.what());
    }
  }
  return search;
}

FoundCheckpoint find_checkpoint(const fs::path& from, double time_ms) {
  if (fs::is_regular_file(from)) return {from, read_checkpoint_file(from), {}};
  if (!fs::is_directory(from)) throw CheckpointError(from.string() + " is neither a checkpoint file nor a run's folder");
  const auto files = list_checkpoints(from);
  if (files.empty()) throw CheckpointError(from.string() + " holds no checkpoints (run it with output.checkpoint)");
  if (time_ms < 0) return {files.front(), read_checkpoint_file(files.front()), {}};
  std::string times;
  for (const auto& file : files) {
    const double t = static_cast<double>(time_in_name(file)) / 1000.0;
    if (std::abs(t - time_ms) <= 5e-4) return {file, read_checkpoint_file(file), {}};
    times = fmt::format("{:g}", t) + (times.empty() ? "" : ", ") + times;
  }
  throw CheckpointError(fmt::format("{} has no checkpoint at t = {:g} ms; it has {} ms", from.string(), time_ms, times));
}

}  // namespace fibrodem
