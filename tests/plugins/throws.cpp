// A test model whose evaluate() throws once its time passes 5 ms (the plugin
// contract forbids it): the run must stop naming the model, outputs kept.
#include <stdexcept>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {
class Throws final : public fibrodem::CellModel {
 public:
  Throws() {
    info_.name = "throws";
    info_.version = "test";
    info_.states = {{"V", "mV", -50.0, -500.0, 500.0, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double t_ms) const override {
    if (t_ms > 5) throw std::domain_error("lookup out of range at t = 5+ ms");
    for (std::size_t c = block.begin; c < block.end; ++c) {
      const fibrodem::CellAccess cell(block, c);
      cell.rate(0, cell.input(0) / cell.param(0));
    }
  }

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Throws)
