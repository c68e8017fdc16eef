// How work over cells is split between threads.
#pragma once

#include <cstddef>

namespace fibrodem {

// Cells per block handed to one thread at a time: small enough that a
// block's states and derivatives stay in the core's L2 cache between its
// evaluation and its update (27 states x 3 arrays x 256 cells = 166 kB).
inline constexpr std::size_t kCellsPerBlock = 256;

// Simple loops over cells (gathers, biomarker tracking) run in parallel only
// from this many cells on: below, a parallel region costs more than the loop
// (at 3129 cells, ~3 us of work; a fork and join costs as much on an idle
// machine and far more when another job holds a core).
inline constexpr long kParallelCells = 32768;

}  // namespace fibrodem
