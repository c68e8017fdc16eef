// A checkpoint written by a run split over N ranks (or in one process: one
// part), cut again for a run split over M (fibrodem resume on another count;
// docs/guide/parallel.md). Each rank of the new run reads every part and
// puts together the fields it would have written itself at that time: each
// field with one entry a cell is taken cell by cell from the part that held
// the cell; the rest (the time, the step count, rank 0's outputs and DEM)
// come from the checkpoint itself, rank 0's part.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/checkpoint_file.hpp"

namespace fibrodem {

// Where each cell of the tissue is in a checkpoint's parts: part and index
// in that part's list of cells (a population's, or a rank's own cells).
class CellPlaces {
 public:
  // cells_of_part[r]: the cells part r's field lists, in its order.
  CellPlaces(const std::vector<std::vector<int>>& cells_of_part, std::size_t tissue_cells);

  // Field `name` of the parts, `rows` of values a cell, row k holding every
  // cell's k-th (value k * n + i for n cells, as Population::y), taken for
  // `cells` in their order. Throws CheckpointError naming the field if a
  // part's length is no multiple of its cells or a cell is in no part.
  std::vector<double> rows(const std::vector<CheckpointFields>& parts, const std::string& name,
                           const std::vector<int>& cells) const;
  // Field `name` of the parts, the same number of bytes a cell one after
  // another (cell i's at i * width), taken for `cells`.
  std::string bytes(const std::vector<CheckpointFields>& parts, const std::string& name,
                    const std::vector<int>& cells) const;

 private:
  std::vector<int> part_, index_;  // per tissue cell; part -1: in none
  std::vector<std::size_t> part_cells_;
  std::size_t where(int cell, const std::string& name) const;
  // std::invalid_argument unless there is a part for each list of cells.
  void check_parts(const std::vector<CheckpointFields>& parts) const;
};

// The number of ranks a checkpoint (rank 0's part: the checkpoint itself)
// was written over: 1 for a run in one process, whose checkpoints carry none.
long long ranks_of_checkpoint(const CheckpointFields& checkpoint);
// Rank r's part of the checkpoint `file` whose own fields are `checkpoint`
// (rank r > 0: the file beside it, run/checkpoint_dir.hpp), checked to be
// that rank's part of the same time. Throws CheckpointError naming the part.
CheckpointFields read_checkpoint_part(const std::filesystem::path& file, const CheckpointFields& checkpoint, int rank);
// Every part, rank 0's (`checkpoint`, moved in) first.
std::vector<CheckpointFields> read_checkpoint_parts(const std::filesystem::path& file, CheckpointFields checkpoint);

// Each part's own cells in increasing order (its biomarker tracker's): the
// cells of its ionic populations ("ionic.*.cells").
std::vector<std::vector<int>> own_cells_of_parts(const std::vector<CheckpointFields>& parts);

}  // namespace fibrodem
