#include "tissue/cell_stream.hpp"

#include <utility>

namespace fibrodem {

namespace {

class HeldTissueStream final : public CellStream {
 public:
  explicit HeldTissueStream(Tissue tissue) : tissue_(std::move(tissue)) {}

  Tissue cell_types() const override {
    Tissue types;
    types.release_unbuilt_particles(tissue_.built_particles(), tissue_.built_bonds(), tissue_.bounds_um());
    types.type = tissue_.type;  // (after: a tissue without particles would take its bounds from its centres)
    return types;
  }
  void for_each_cell(const std::function<void(int, CellType, double, double)>& visit) const override {
    tissue_.for_each_cell(visit);
  }
  void for_each_edge(const std::function<void(const CellCentre&, const CellCentre&)>& visit) const override {
    for (const auto& [a, b] : tissue_.cell_edges) visit(tissue_.centre_of(a), tissue_.centre_of(b));
  }

 private:
  Tissue tissue_;
};

}  // namespace

std::unique_ptr<CellStream> stream_of(Tissue tissue) { return std::make_unique<HeldTissueStream>(std::move(tissue)); }

}  // namespace fibrodem
