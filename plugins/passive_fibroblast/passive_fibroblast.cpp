// Passive fibroblast: a capacitor in parallel with a linear leak.
//   C dV/dt = -(V - E_rev)/R + i_ext
// Parameters as defined by MacCannell et al. 2007 (Biophys J 92:4121) and used by
// ELECTRA's passive fibroblast (lino202/ELECTRA src/.../passive.cpp):
// C = 6.3 pF, R = 10.7 GOhm, E_rev = -49.6 mV (tau_m = RC = 67.4 ms).
// Units: mV / GOhm = pA, pA / pF = mV/ms.
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {


enum State { kV };
enum Param { kC_pF, kR_GOhm, kE_rev_mV };
enum Input { kI_ext_pA };
enum Output { kI_ion_pA };

class PassiveFibroblast final : public fibrodem::CellModel {
 public:
  PassiveFibroblast() {
    info_.name = "passive_fibroblast";
    info_.version = "1.0.0";
    info_.description = "Passive fibroblast: membrane capacitance and a linear leak.";
    info_.reference =
        "MacCannell KA et al. Biophys J 92:4121-4132 (2007), passive model values";
    info_.kind = fibrodem::ModelKind::ionic;
    info_.states = {{"V", "mV", -49.6, -500.0, 500.0, false}};
    info_.parameters = {
        {"C_pF", "pF", 6.3, "membrane capacitance"},
        {"R_GOhm", "GOhm", 10.7, "membrane resistance"},
        {"E_rev_mV", "mV", -49.6, "reversal (resting) potential"},
    };
    info_.inputs = {{"i_ext", "pA", "stimulus and gap-junction current, + depolarising"}};
    info_.outputs = {{"I_ion", "pA", "leak current, + outward"}};
    info_.voltage_state = kV;
    info_.capacitance_parameter = kC_pF;
  }

  const fibrodem::ModelInfo& info() const override { return info_; }

  void evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const override {
    const double C = block.params[kC_pF];
    const double R = block.params[kR_GOhm];
    const double E = block.params[kE_rev_mV];
    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using Real = typename std::decay_t<decltype(cell)>::Real;
      const Real V = cell.state(kV);
      const Real I_leak_pA = (V - E) / R;
      cell.rate(kV, (cell.input(kI_ext_pA) - I_leak_pA) / C);
      cell.output(kI_ion_pA, I_leak_pA);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};

}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(PassiveFibroblast)
