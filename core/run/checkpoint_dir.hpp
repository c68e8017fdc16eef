// A run's checkpoints (output.checkpoint): DIR/checkpoints/t_<time in us>.ckpt,
// one per checkpoint time, the newest `keep` of them kept.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/checkpoint_file.hpp"

namespace fibrodem {

std::filesystem::path checkpoint_path(const std::filesystem::path& run_dir, double t_ms);
// A run split over MPI ranks (docs/guide/parallel.md): rank r > 0's part of the
// checkpoint `checkpoint` (checkpoint_path's), beside it:
// t_<time in us>us.rank<r>.ckpt. list_checkpoints does not list these;
// prune_checkpoints removes them with their checkpoint.
std::filesystem::path rank_checkpoint_path(const std::filesystem::path& checkpoint, int rank);
// The checkpoint files of a run, newest (latest time) first.
std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& run_dir);
// Removes all but the newest `keep` (and the rank parts of those removed).
void prune_checkpoints(const std::filesystem::path& run_dir, int keep);
// Removes them all (a new run into a folder that held another).
void clear_checkpoints(const std::filesystem::path& run_dir);

struct FoundCheckpoint {
  std::filesystem::path file;
  CheckpointFields fields;
  std::vector<std::string> skipped;  // newer files that could not be read, each with why
};
struct CheckpointSearch {
  std::optional<FoundCheckpoint> found;
  std::vector<std::string> skipped;  // the files that could not be read, each with why
};
// The newest checkpoint that reads back whole (checksum and all), if any,
// and the newer ones passed over.
CheckpointSearch latest_good_checkpoint(const std::filesystem::path& run_dir);

// A checkpoint named by initial_state.from: a checkpoint file, or a run's
// folder with time_ms choosing its checkpoint at that time (< 0: the
// latest). Throws CheckpointError naming the file or listing the times there are.
FoundCheckpoint find_checkpoint(const std::filesystem::path& from, double time_ms);

}  // namespace fibrodem
