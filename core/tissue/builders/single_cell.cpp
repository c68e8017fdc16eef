// `single_cell`: one isolated cell of the given type.
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

class SingleCellBuilder final : public TissueBuilder {
 public:
  explicit SingleCellBuilder(CellType type) : type_(type) {}
  Tissue build(std::uint64_t /*seed*/) const override {
    Tissue tissue;
    if (type_ == CellType::myocyte) add_vertical_myocyte(tissue, 0.0, 0.0);
    else add_round_fibroblast(tissue, 0.0, 0.0);
    tissue.finalise();
    return tissue;
  }

 private:
  CellType type_;
};

}  // namespace

std::unique_ptr<TissueBuilder> make_single_cell_builder(JsonReader& tissue) {
  return std::make_unique<SingleCellBuilder>(read_cell_type(tissue, "type", CellType::myocyte));
}

}  // namespace fibrodem
