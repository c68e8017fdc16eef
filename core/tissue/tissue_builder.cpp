#include "tissue/tissue_builder.hpp"

#include <vector>

namespace fibrodem {

Tissue TissueBuilder::build_cells(std::uint64_t seed) const {
  Tissue tissue = build(seed);
  tissue.release_particles();
  return tissue;
}

void TissueBuilder::for_each_particle(std::uint64_t seed, const std::function<void(const Particle&)>& visit) const {
  for (const Particle& p : build(seed).particles) visit(p);
}

std::unique_ptr<CellStream> TissueBuilder::stream_cells(std::uint64_t seed) const {
  return stream_of(build_cells(seed));
}

std::size_t TissueBuilder::cell_count(std::uint64_t seed) const { return build_cells(seed).cell_count(); }

const std::map<std::string, TissueBuilderFactory>& tissue_builders() {
  static const std::map<std::string, TissueBuilderFactory> builders = {
      {"single_cell", make_single_cell_builder},
      {"cell_pair", make_cell_pair_builder},
      {"strand", make_strand_builder},
      {"in_series", make_in_series_builder},
      {"interstitial", make_interstitial_builder},
      {"fibrotic_patch", make_fibrotic_patch_builder},
      {"fibrotic_sheet", make_fibrotic_sheet_builder},
  };
  return builders;
}

std::unique_ptr<TissueBuilder> make_tissue_builder(JsonReader& tissue) {
  std::vector<std::string> names;
  for (const auto& [name, factory] : tissue_builders()) names.push_back(name);
  const std::string name = tissue.text("builder", std::nullopt, names);
  auto builder = tissue_builders().at(name)(tissue);
  tissue.finish();
  return builder;
}

CellType read_cell_type(JsonReader& reader, const std::string& key, CellType fallback) {
  const std::string name = reader.text(key, std::string(cell_type_name(fallback)),
                                       {kCellTypeNames.begin(), kCellTypeNames.end()});
  return name == "myocyte" ? CellType::myocyte : CellType::fibroblast;
}

}  // namespace fibrodem
