// A test model with two states of one name: refused at load, by name.
#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {
class DuplicateStates final : public fibrodem::CellModel {
 public:
  DuplicateStates() {
    info_.name = "duplicate_states";
    info_.version = "test";
    info_.states = {{"V", "mV", -50.0, -500.0, 500.0, false}, {"V", "mV", -50.0, -500.0, 500.0, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView&, double) const override {}

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(DuplicateStates)
