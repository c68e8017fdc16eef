// `strand`: a chain of N cells of one type along the fibre (y), end to end,
// each joined to the next by one bond between touching end particles.
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

class StrandBuilder final : public TissueBuilder {
 public:
  StrandBuilder(CellType type, int cells) : type_(type), cells_(cells) {}

  Tissue build(std::uint64_t /*seed*/) const override {
    Tissue tissue;
    int previous_end = -1;  // top particle of the previous cell
    for (int k = 0; k < cells_; ++k) {
      const int first = static_cast<int>(tissue.particles.size());
      if (type_ == CellType::myocyte)
        add_vertical_myocyte(tissue, 0.0, k * kMyocyteLength_um);
      else
        add_round_fibroblast(tissue, 0.0, kParticleRadius_um + k * 2 * kParticleRadius_um);
      if (previous_end >= 0) tissue.add_bond(previous_end, first);
      previous_end = static_cast<int>(tissue.particles.size()) - 1;
    }
    tissue.finalise();
    return tissue;
  }

 private:
  CellType type_;
  int cells_;
};

}  // namespace

std::unique_ptr<TissueBuilder> make_strand_builder(JsonReader& tissue) {
  const CellType type = read_cell_type(tissue, "type", CellType::myocyte);
  const int cells = static_cast<int>(tissue.integer("cells", std::nullopt, 1, 1000000));
  return std::make_unique<StrandBuilder>(type, cells);
}

}  // namespace fibrodem
