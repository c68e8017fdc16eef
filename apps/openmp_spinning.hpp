// OpenMP's idle threads wait for the next parallel loop by spinning: GCC's
// libgomp spins ~300,000 times (milliseconds) before it sleeps, which on a
// shared machine takes a core from other jobs. A run's parallel loops come
// microseconds apart, so a short spin (GOMP_SPINCOUNT=10000, ~0.1 ms) keeps
// them fast and lets idle threads sleep (docs/topics/performance.md#how).
// libgomp reads the setting only when it loads, before main(): the process
// has to start itself again with it, which loads every library a second
// time (about as long as a whole single-cell run's start-up). So only a
// command that will open a team of threads restarts, once it knows it will.
#pragma once

#include "scene/scene.hpp"
#include "util/json_reader.hpp"

namespace fibrodem::cli {

// Keeps argv for a restart (main() calls this first).
void keep_arguments(char** argv);

// Starts the program again with GOMP_SPINCOUNT=10000 unless the user chose a
// policy (OMP_WAIT_POLICY or GOMP_SPINCOUNT set), binds OpenMP's threads to
// places (OMP_PLACES, or OMP_PROC_BIND other than false) or this process is
// that restart; returns only if it does not restart (or the restart failed: then
// the program runs as it is). Call it before anything with a side effect.
void bound_openmp_spinning();

// Whether a run of `scene` can open a team of more than one OpenMP thread:
// not when solver.threads is 1, nor on one cell under solver.threads "auto"
// (run/simulation_assembly.cpp gives a scene that small one thread), where
// the restart would cost more than the run.
bool may_use_thread_team(const Scene& scene, const json& manifest);

}  // namespace fibrodem::cli
