// A test model that takes its process down (SIGSEGV) when its parameter
// `crash` is above 0.5: a sweep must survive it in its other points.
#include <csignal>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {
class Crashes final : public fibrodem::CellModel {
 public:
  Crashes() {
    info_.name = "crashes";
    info_.version = "test";
    info_.states = {{"V", "mV", -50.0, -500.0, 500.0, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}, {"crash", "1", 0.0, "above 0.5: SIGSEGV"}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double) const override {
    if (block.params[1] > 0.5) std::raise(SIGSEGV);
    for (std::size_t c = block.begin; c < block.end; ++c) {
      const fibrodem::CellAccess cell(block, c);
      cell.rate(0, cell.input(0) / cell.param(0));
    }
  }

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Crashes)
