// A TissueBuilder makes the tissue of a scene from its manifest section
// (`tissue`), deterministically for a seed. Builders are registered by name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "tissue/cell_stream.hpp"
#include "tissue/tissue.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

class TissueBuilder {
 public:
  virtual ~TissueBuilder() = default;
  virtual Tissue build(std::uint64_t seed) const = 0;

  // For a process that never needs the particles and bonds together (a rank
  // of a split run without mechanics: docs/guide/parallel.md): the tissue's
  // cells, their centres and graph, as build() makes them, its particles
  // and bonds released (Tissue::release_particles: their counts and bounds
  // kept); and each cell's particle in build()'s order, one at a time.
  // By default both build the whole tissue; a builder that makes them
  // without it says so (builds_cells_alone), and build_cells then takes
  // about the cells' own memory.
  virtual Tissue build_cells(std::uint64_t seed) const;
  virtual void for_each_particle(std::uint64_t seed, const std::function<void(const Particle&)>& visit) const;
  virtual bool builds_cells_alone() const { return false; }
  // For a process that keeps part of the cells and of their graph (a rank
  // of a split run without mechanics, cut by the cells' centres):
  // build_cells()'s cells, centres and graph handed over one at a time
  // (tissue/cell_stream.hpp). By default from build_cells(), which the
  // stream holds.
  virtual std::unique_ptr<CellStream> stream_cells(std::uint64_t seed) const;
  // The tissue's cell count (build_cells()'s), for a choice made before the
  // tissue is built (solver.method "auto" over ranks). By default from
  // build_cells().
  virtual std::size_t cell_count(std::uint64_t seed) const;
};

// Reads a builder's own parameters from the `tissue` object (its `builder` key
// already read) and returns the builder; errors name the JSON path.
using TissueBuilderFactory = std::function<std::unique_ptr<TissueBuilder>(JsonReader&)>;

const std::map<std::string, TissueBuilderFactory>& tissue_builders();

// Reads `tissue.builder` and the builder's parameters; rejects unknown keys.
std::unique_ptr<TissueBuilder> make_tissue_builder(JsonReader& tissue);

// Each builder's factory, defined in builders/<name>.cpp.
std::unique_ptr<TissueBuilder> make_single_cell_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_cell_pair_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_strand_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_in_series_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_interstitial_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_fibrotic_patch_builder(JsonReader& tissue);
std::unique_ptr<TissueBuilder> make_fibrotic_sheet_builder(JsonReader& tissue);

// Reads a `type` key naming a cell type.
CellType read_cell_type(JsonReader& reader, const std::string& key, CellType fallback);

}  // namespace fibrodem
