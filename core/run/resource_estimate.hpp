// Memory and output size of a scene, estimated before it runs: a scene that would not fit in the machine's memory
// or on the output disk is refused with the estimate and what to change.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "integrate/cell_system.hpp"
#include "scene/scene.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct ResourceEstimate {
  struct Part {
    std::string what;   // "traces: 2 cells x 1 variable x 10001 samples"
    double bytes = 0;
    std::string remedy;  // what would shrink it
  };
  std::vector<Part> memory, output;
  double memory_bytes() const;
  double output_bytes() const;
  std::string describe() const;  // "memory ~12 MB (...), output ~3 MB (...)"
};

// The estimate for a scene whose cells, models and coupling are built.
// Split over ranks, `rank`'s (of `ranks`): the system's populations hold
// its own cells, whose states, trackers and coupling rows it keeps; rank 0
// alone keeps what it gathers from every rank for the outputs (pictures,
// maps, re-entry frames, every beat); `mechanics`: this rank holds the
// DEM (every rank when the DEM is split, else rank 0).
ResourceEstimate estimate_resources(const Scene& scene, const Tissue& tissue, const CellSystem& system,
                                    bool mechanics, int rank = 0, int ranks = 1);

// The DEM's memory for a tissue (its bodies, particles with the collagen's,
// and bonds), and the check made before the DEM is built: throws
// ManifestError (path `tissue`) with the estimate if it alone exceeds 0.9 x
// `available_memory_bytes`.
ResourceEstimate::Part dem_memory(const Tissue& tissue);
void check_dem_memory(const Tissue& tissue, double available_memory_bytes);

// Throws ManifestError naming the largest part and its remedy if the memory
// estimate exceeds `available_memory_bytes` or the output estimate exceeds
// `available_disk_bytes`.
void check_resources(const ResourceEstimate& estimate, double available_memory_bytes, double available_disk_bytes);

// This machine's available memory (MemAvailable), and the space free where
// `dir` is (infinity if unknown).
double available_memory_bytes();
double available_disk_bytes(const std::filesystem::path& dir);

}  // namespace fibrodem
