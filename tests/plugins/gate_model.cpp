// A small ionic model (V, one voltage-only gate n, a concentration Ca_i) for
// `fibrodem check-plugin`'s tests, built once well behaved and once per
// deliberate fault (GATE_MODEL_FAULT, see tests/CMakeLists.txt):
//   0 well_behaved          passes every check
//   1 frozen_gate           evaluate() never writes n's a and b
//   2 initial_out_of_bounds n starts at 1.5, outside [0, 1]
//   3 voltage_only_on_ca    n is marked voltage_only but its tau depends on Ca_i
// Equations: I = g n (V - E); n_inf = 1/(1 + exp(-(V + 20)/9)), tau_n 50 ms;
// dCa/dt = 1e-6 n - Ca/100 (mM/ms).
#include "model/block_access.hpp"
#include "model/cell_model.hpp"

#ifndef GATE_MODEL_FAULT
#define GATE_MODEL_FAULT 0
#endif

namespace {
FIBRODEM_USE_LANE_MATH;

class GateModel final : public fibrodem::CellModel {
 public:
  GateModel() {
    info_.name = GATE_MODEL_NAME;
    info_.version = "test";
    const double n0 = GATE_MODEL_FAULT == 2 ? 1.5 : 0.03;
    info_.states = {{"V", "mV", -50.0, -200.0, 200.0, false},
                    {"n", "1", n0, 0.0, 1.0, true, true},
                    {"Ca_i", "mM", 3e-7, 0.0, 1.0, false}};
    info_.parameters = {{"C_pF", "pF", 10.0, ""}, {"g_nS", "nS", 1.0, ""}, {"E_mV", "mV", -80.0, ""}};
    info_.inputs = {{"i_ext", "pA", ""}};
    info_.outputs = {{"I_ion", "pA", ""}};
    info_.voltage_state = 0;
    info_.capacitance_parameter = 0;
  }
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double) const override {
    const double C = block.params[0], g = block.params[1], E = block.params[2];
    const bool skip_n = block.skip_voltage_only_gates;
    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using R = typename std::decay_t<decltype(cell)>::Real;
      const R V = cell.state(0), n = cell.state(1), Ca = cell.state(2);
      const R n_inf = 1.0 / (1.0 + exp(-(V + 20.0) / 9.0));
      const R tau = GATE_MODEL_FAULT == 3 ? R(50.0) / (1.0 + 1000.0 * Ca) : R(50.0);
      if (GATE_MODEL_FAULT != 1 && !skip_n) cell.gate_inf_tau(1, n_inf, tau);
      cell.linear(2, 1e-6 * n, R(-1.0 / 100.0));
      const R I = g * n * (V - E);
      cell.rate(0, (cell.input(0) - I) / C);
      cell.output(0, I);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};
}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(GateModel)
