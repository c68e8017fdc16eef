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

// f(k) for each of `count` blocks of cells, shared dynamically between the
// OpenMP threads (blocks differ in cost; each depends only on its own cells,
// so the thread count changes nothing). One block runs on the calling thread
// without an OpenMP region: even a region whose if() is false costs libgomp an
// allocation and a futex call, which a single cell pays at every step (CVODE:
// thousands of times per simulated second).
template <class F>
void for_each_block(long count, F&& f) {
  if (count == 1) return f(0L);
#pragma omp parallel for schedule(dynamic, 1)
  for (long k = 0; k < count; ++k) f(k);
}

// f(i) for i in [0, n): on the OpenMP threads from kParallelCells on, else a
// plain loop (not an `omp parallel for if(...)`, as for_each_block says).
template <class F>
void for_each_cell(long n, F&& f) {
  if (n <= kParallelCells) {
    for (long i = 0; i < n; ++i) f(i);
    return;
  }
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) f(i);
}

}  // namespace fibrodem
