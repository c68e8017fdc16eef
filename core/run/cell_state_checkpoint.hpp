// The cells' part of a checkpoint: every population's states, inputs and
// outputs (ionic and myofilament), the myofilaments' rest lengths, and what
// identifies them (model, state names, cells), so that a checkpoint is
// loaded only into the same tissue and models.
#pragma once

#include <string>
#include <vector>

#include "integrate/cell_system.hpp"
#include "io/checkpoint_file.hpp"

namespace fibrodem {

void save_cell_states(const CellSystem& system, CheckpointFields& fields);

// Throws CheckpointError naming what differs (a population's model, its
// states, its cells) when the checkpoint was not written for this system.
void check_same_cells(const CellSystem& system, const CheckpointFields& fields);

// check_same_cells, then the states (and, with everything, inputs, outputs,
// rest lengths and the last step: a resumed run; without, the states alone:
// a new run started from them).
void load_cell_states(CellSystem& system, const CheckpointFields& fields, bool everything);

// The cells' fields a system holding some of the tissue's cells (a rank's
// share of a run split over ranks, or the whole tissue) would have written
// (save_cell_states), put together from a checkpoint's parts taken one at
// a time (one for a run in one process, one a rank for a split run, rank
// 0's first: run/checkpoint_recut.hpp): each population's cells' states,
// inputs, outputs and rest lengths, picked out by cell number.
class CellStatesRecut {
 public:
  // Throws CheckpointError as check_same_cells does, but for the cells
  // (`checkpoint`: rank 0's part). With states_only, the states alone are
  // taken (a new run started from them).
  CellStatesRecut(const CellSystem& system, const CheckpointFields& checkpoint, bool states_only);
  ~CellStatesRecut();
  void take(const CheckpointFields& part, int r);
  bool complete() const;  // every population's cells found
  // Once every part is taken (CheckpointError when a population's cell is
  // in no part): the fields, into `out`; or the states into the system.
  void put_into(CheckpointFields& out) const;
  void load_states(CellSystem& system);

 private:
  struct Picked;
  std::vector<Picked> populations_;
};

}  // namespace fibrodem
