// The cells' part of a checkpoint: every population's states, inputs and
// outputs (ionic and myofilament), the myofilaments' rest lengths, and what
// identifies them (model, state names, cells), so that a checkpoint is
// loaded only into the same tissue and models.
#pragma once

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
// some of the tissue's cells (a rank's share of a run split over ranks) from
// a checkpoint of the whole tissue (a run in one process): each population's
// cells' states picked out of the checkpoint's by cell number. Throws
// CheckpointError as check_same_cells does, and when a population's cell is
// not among the checkpoint's.
void load_own_cell_states(CellSystem& system, const CheckpointFields& fields);

}  // namespace fibrodem
