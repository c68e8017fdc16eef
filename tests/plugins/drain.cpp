// A test model whose concentration drains at a constant rate, so that it
// crosses zero at a known time: the state-bounds check must catch and name it.
#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {
class Drain final : public fibrodem::CellModel {
 public:
  Drain() {
    info_.name = "drain";
    info_.version = "test";
    info_.states = {{"V", "mV", -50.0, -500.0, 500.0, false}, {"X_i", "mM", 1.0, 0.0, 1e3, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}, {"drain_mM_per_ms", "mM/ms", 0.01, ""}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.outputs = {{"I_ion", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double) const override {
    for (std::size_t c = block.begin; c < block.end; ++c) {
      const fibrodem::CellAccess cell(block, c);
      cell.rate(0, cell.input(0) / cell.param(0));
      cell.rate(1, -cell.param(1));
      cell.output(0, 0.0);
    }
  }

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Drain)
