// The cells' part of a checkpoint: every population's states, inputs and
// outputs (ionic and myofilament), the myofilaments' rest lengths, and what
// identifies them (model, state names, cells), so that a checkpoint is
// loaded only into the same tissue and models.
#pragma once

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

// The states alone (a new run started from them) of a system that holds
// some of the tissue's cells (a rank's share of a run split over ranks, or
// the whole tissue) from a checkpoint's parts (one for a run in one process,
// one a rank for a split run, rank 0's first): each population's cells'
// states picked out by cell number. Throws CheckpointError as
// check_same_cells does, and when a population's cell is in no part.
void load_own_cell_states(CellSystem& system, const std::vector<CheckpointFields>& parts);

// The cells' fields a system holding some of the tissue's cells would have
// written (save_cell_states), put into `out` from a checkpoint's parts
// (run/checkpoint_recut.hpp): each population's cells, states, inputs,
// outputs and rest lengths, for its own cells.
void recut_cell_states(const std::vector<CheckpointFields>& parts, const CellSystem& system, CheckpointFields& out);

}  // namespace fibrodem
