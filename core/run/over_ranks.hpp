// What `fibrodem run` can split over the ranks of an mpirun (docs/guide/parallel.md):
// the electrophysiology of one tissue with the adaptive method or a
// fixed-step one (euler, rush_larsen, rush_larsen2), explicit or implicit
// gap-junction coupling, contraction, mechano-electric feedback and the
// mechanics (the DEM split too: mechanics/dem_split.hpp; or stepped on
// rank 0: run/mechanics_over_ranks.hpp),
// settle, initial_state.from (a one-process checkpoint), its biomarkers,
// traces of states and strain, snapshots, re-entry, maps, summary and
// checkpoints (resumed on as many ranks). Anything else (CVODE) stops on
// every rank with the message below before anything is written, instead of
// N processes writing one folder. (`fibrodem sweep` spreads whole runs over
// ranks.)
#pragma once

#include <string>
#include <vector>

#include "scene/effects.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Each part of the scene that a run over several ranks cannot take, as a
// phrase naming it and where the manifest asks for it; empty: it can run
// split. `method` is the solver's method once "auto" has chosen.
std::vector<std::string> unsupported_over_ranks(const Scene& scene, const std::string& method);
// The same from the scene alone (builds its tissue when solver.method is
// "auto": what it chooses follows from the cell count).
std::vector<std::string> unsupported_over_ranks(const Scene& scene);

// What a rank of a run split over `ranks` keeps of the cells' layout once
// the run has started (run/simulation_ranks.cpp frees the rest before the
// stepping's arrays are made; validate counts what it keeps): the cell graph
// where the scene has mechanics (each rank measures its cells' stretch along
// it) or on rank 0 with re-entry measures, the cells' centres where the
// scene has mechanics or on rank 0 (conduction velocity, maps, re-entry).
// In one process, everything.
struct CellLayoutKept {
  bool graph = true, centres = true;
};
CellLayoutKept cell_layout_kept(int rank, int ranks, bool mechanics, bool reentry);

// The error every rank stops with: the command, the rank count, what is
// unsupported and what to do instead.
std::string refusal_over_ranks(const std::string& command, int ranks, const std::vector<std::string>& unsupported);

}  // namespace fibrodem
