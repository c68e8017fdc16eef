// A TissueBuilder makes the tissue of a scene from its manifest section
// (`tissue`), deterministically for a seed. Builders are registered by name.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "util/json_reader.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

class TissueBuilder {
 public:
  virtual ~TissueBuilder() = default;
  virtual Tissue build(std::uint64_t seed) const = 0;
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
