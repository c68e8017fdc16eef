// A test model that breaks the plugin contract on request, through its
// parameter `fault`: 1, evaluate() throws once t passes 5 ms (the run must
// stop naming the model, outputs kept); 2, it takes its process down with
// SIGSEGV (a sweep must survive it in its other points); 3, V's rate turns
// NaN once t passes 5 ms (a model bug, whatever the step); 0, it behaves.
#include <cmath>
#include <csignal>
#include <stdexcept>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {
class Misbehaves final : public fibrodem::CellModel {
 public:
  Misbehaves() {
    info_.name = "misbehaves";
    info_.version = "test";
    info_.states = {{"V", "mV", -50.0, -500.0, 500.0, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}, {"fault", "1", 0.0, "1: throw after 5 ms; 2: SIGSEGV; 3: NaN rate after 5 ms"}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double t_ms) const override {
    const double fault = block.params[1];
    if (fault == 1 && t_ms > 5) throw std::domain_error("lookup out of range at t = 5+ ms");
    if (fault == 2) std::raise(SIGSEGV);
    for (std::size_t c = block.begin; c < block.end; ++c) {
      const fibrodem::CellAccess cell(block, c);
      cell.rate(0, fault == 3 && t_ms > 5 ? std::nan("") : cell.input(0) / cell.param(0));
    }
  }

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Misbehaves)
