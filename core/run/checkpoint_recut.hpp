// A checkpoint written by a run split over N ranks (or in one process: one
// part), cut again for a run split over M (fibrodem resume on another count;
// docs/guide/parallel.md). Each rank of the new run reads the parts one at a
// time and keeps, of each, what it would have written itself at that time:
// each field with one entry a cell is taken cell by cell from the part that
// held the cell; the rest (the time, the step count, rank 0's outputs and
// DEM) come from the checkpoint itself, rank 0's part. So a rank holds one
// part at a time beside what it keeps.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "io/checkpoint_file.hpp"

namespace fibrodem {

// Fields of some of the tissue's cells (the picked cells, in the fields'
// order) put together from a checkpoint's parts, taken one at a time.
class CellPick {
 public:
  CellPick(const std::vector<int>& cells, std::size_t tissue_cells);
  const std::vector<int>& cells() const { return cells_; }
  // Whether `cell` (any number: one outside the tissue is not) is picked.
  bool picks(int cell) const {
    return cell >= 0 && static_cast<std::size_t>(cell) < place_.size() && place_[static_cast<std::size_t>(cell)] >= 0;
  }

  // From part r, whose fields list `part_cells` in their order: of each
  // field in `rows` (values k * n + j for its n cells, a whole number of
  // rows: as Population::y) and in `bytes` (the same number of bytes a
  // cell, cell j's at j * width), the picked cells' values. A part with no
  // cells may lack the fields. Throws CheckpointError naming the field if a
  // part's length is no multiple of its cells or its rows differ from an
  // earlier part's, and naming the cell if `part_cells` lists one this
  // tissue lacks or an earlier part listed.
  void take(const CheckpointFields& part, int r, const std::vector<int>& part_cells,
            const std::vector<std::string>& rows, const std::vector<std::string>& bytes = {});
  // Once every part is taken: the fields, into `out`. Throws
  // CheckpointError naming a picked cell that no part held.
  void put_into(CheckpointFields& out) const;
  // Whether every picked cell has been found in a part taken.
  bool complete() const;
  // The same for one field of rows, moved out.
  std::vector<double> release_rows(const std::string& name);

 private:
  void check_complete(const std::string& name) const;
  std::size_t picked() const { return cells_.size(); }

  std::vector<int> cells_;
  std::vector<int> place_;            // per tissue cell: its place among the picked; -1: not picked
  std::vector<char> listed_;          // per tissue cell: listed by a part taken
  std::vector<char> found_;           // per picked cell
  struct Rows {
    std::vector<double> values;
    std::size_t rows = 0;
    bool started = false;
  };
  std::map<std::string, Rows> rows_;
  std::map<std::string, std::pair<std::string, std::size_t>> bytes_;  // values, width (0: not started)
};

// The parts of the checkpoint `file` whose own fields are `checkpoint`
// (rank 0's), each read and handed to visit(part, r) in turn, then dropped:
// rank 0's first, as it is, then those in `likely`, then, while
// complete() says a cell is still missing, the others. Returns how many
// parts were read. (A run split as the checkpoint's was finds a rank's
// cells in the parts its partition says: run/simulation_checkpoints.cpp.)
int take_checkpoint_parts(const std::filesystem::path& file, const CheckpointFields& checkpoint,
                          const std::vector<int>& likely, const std::function<bool()>& complete,
                          const std::function<void(const CheckpointFields& part, int r)>& visit);

// The number of ranks a checkpoint (rank 0's part: the checkpoint itself)
// was written over: 1 for a run in one process, whose checkpoints carry none.
long long ranks_of_checkpoint(const CheckpointFields& checkpoint);
// Rank r's part of the checkpoint `file` whose own fields are `checkpoint`
// (rank r > 0: the file beside it, run/checkpoint_dir.hpp), checked to be
// that rank's part of the same time. Throws CheckpointError naming the part.
CheckpointFields read_checkpoint_part(const std::filesystem::path& file, const CheckpointFields& checkpoint, int rank);

// A part's own cells in increasing order (its biomarker tracker's): the
// cells of its ionic populations ("ionic.*.cells").
std::vector<int> own_cells_of_part(const CheckpointFields& part);

}  // namespace fibrodem
