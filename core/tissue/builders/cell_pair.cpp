// `cell_pair`: one myocyte (cell 0) coupled to N fibroblasts, each fibroblast
// coupled only to the myocyte (Maleckar et al. 2009's myocyte-fibroblast pair
// with N_f fibroblasts). Fibroblasts sit against the myocyte's particles, left
// and right alternately from the bottom, then at its two ends.
#include "tissue/tissue_builder.hpp"

namespace fibrodem {
namespace {

constexpr int kMaxFibroblasts = 2 * kMyocyteParticles + 2;

class CellPairBuilder final : public TissueBuilder {
 public:
  explicit CellPairBuilder(int fibroblasts) : fibroblasts_(fibroblasts) {}

  Tissue build(std::uint64_t /*seed*/) const override {
    Tissue tissue;
    add_vertical_myocyte(tissue, 0.0, 0.0);
    const double touch = 2 * kParticleRadius_um;
    for (int k = 0; k < fibroblasts_; ++k) {
      int anchor;  // the myocyte particle this fibroblast touches
      double x, y;
      if (k < 2 * kMyocyteParticles) {
        anchor = k / 2;
        x = (k % 2 == 0 ? -touch : touch);
        y = tissue.particles[anchor].y_um;
      } else {
        anchor = (k % 2 == 0) ? 0 : kMyocyteParticles - 1;
        x = 0.0;
        y = tissue.particles[anchor].y_um + (k % 2 == 0 ? -touch : touch);
      }
      add_round_fibroblast(tissue, x, y);
      tissue.add_bond(anchor, static_cast<int>(tissue.particles.size()) - 1);
    }
    tissue.finalise();
    return tissue;
  }

 private:
  int fibroblasts_;
};

}  // namespace

std::unique_ptr<TissueBuilder> make_cell_pair_builder(JsonReader& tissue) {
  return std::make_unique<CellPairBuilder>(
      static_cast<int>(tissue.integer("fibroblasts", 1, 0, kMaxFibroblasts)));
}

}  // namespace fibrodem
