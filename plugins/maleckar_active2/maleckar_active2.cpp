// Active human atrial fibroblast, "active 2" of Maleckar et al. 2009 as used by the
// seed paper (Brocklehurst, Zhang, Ye, Front Physiol 13:938497, 2022): membrane
// currents of MacCannell et al. 2007 with ODEs for V_f and for intracellular K+ and
// Na+.
//   Maleckar MM, Greenstein JL, Giles WR, Trayanova NA. Electrotonic coupling between
//   human atrial myocytes and fibroblasts alters myocyte excitability and
//   repolarization. Biophys J 97:2179-2190 (2009).
//   MacCannell KA, Bazzazi H, Chilton L, Shibukawa Y, Clark RB, Giles WR. A mathematical
//   model of electrotonic interactions between ventricular myocytes and fibroblasts.
//   Biophys J 92:4121-4132 (2007).
//
// Currents (pA/pF; V, E in mV; tau in ms):
//   I_Kv  = G_Kv r s (V - E_K)
//     r_inf = 1/(1+exp(-(V+20-shift)/11)),  tau_r = 20.3 + 138 exp(-((V+20-shift)/25.9)^2)
//     s_inf = 1/(1+exp((V+23-shift)/7)),    tau_s = 1574 + 5268 exp(-((V+23-shift)/22.7)^2)
//   I_K1  = G_K1 aK1/(aK1+bK1) (V - E_K)
//     aK1 = 0.1/(1+exp(0.06 (V-E_K-200)))
//     bK1 = [3 exp(0.0002 (V-E_K+100)) + exp(0.1 (V-E_K-10))] / (1+exp(-0.5 (V-E_K)))
//   I_NaK = I_NaKmax Ko/(Ko+K_mK) Nai^1.5/(Nai^1.5+K_mNa^1.5) (V-V_rev)/(V-B)
//   I_bNa = G_bNa (V - E_Na)
//   C dV/dt = i_ext - C (I_Kv + I_K1 + I_NaK + I_bNa)
// Intracellular ions (charge-conserving, I in pA, Vol in nL, F in C/mol):
//   dK_i/dt  = -(I_Kv + I_K1 - 2 I_NaK) C 1e-3 / (F Vol)      [mM/ms]
//   dNa_i/dt = -(I_bNa + 3 I_NaK)      C 1e-3 / (F Vol)
// `dynamic_ions` = 0 clamps K_i and Na_i (the MacCannell / ELECTRA form). The
// seed paper does not say which ions carry i_ext (stimulus and gap-junction current);
// by default none (`i_ext_K_fraction` = 0), as in the CRN CellML; 1 lets K+ carry it
// (i_ext enters dK_i/dt with the sign of an inward K+ current).
//
// Pitfalls avoided (see docs/reference/references.md#active-fibroblast): the Na term is Nai^1.5/(Nai^1.5+K_mNa^1.5)
// (not (Nai/(Nai+K_mNa))^1.5); bK1 has its numerator bracketed; the taus use
// exp(-(..)^2). I_NaK has a pole at V = B = -200 mV (a true pole of the model, not a
// removable singularity); V's lower bound is set above it.
//
// Ion environment: Maleckar/Nygren (Maleckar 2009 myocyte; Zhang-lab constants):
// Ko 5.3581, Nao 130.011 mM, T 306.15 K, R 8314 mJ/(mol K), F 96487 C/mol,
// Vol 0.00137 nL, C 6.3 pF (MacCannell). E_K = -84.0 mV at K_i 129.4349 mM, not the
// -87.3 mV that ELECTRA hard-codes (Grandi environment), so the resting potential
// is not MacCannell's -49.6 mV; see the initial values below.
#include <cmath>
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {

FIBRODEM_USE_LANE_MATH;

enum State { kV, kr, ks, kK_i, kNa_i, kNumStates };

enum Param {
  kC_pF,
  kG_Kv,
  kG_K1,
  kG_bNa,
  kI_NaK_max,
  kK_mK,
  kK_mNa,
  kV_rev,
  kB,
  kKv_shift,
  kK_o,
  kNa_o,
  kT,
  kR,
  kF,
  kVol_nL,
  kDynamic_ions,
  kI_ext_K_fraction,
  kNumParams
};

enum Input { kI_ext_pA };

enum Output { kI_ion_pA, kI_Kv_out, kI_K1_out, kI_NaK_out, kI_bNa_out };

// Resting steady state of each variant (i_ext = 0), found offline with a throwaway
// single-cell driver: integrated (Rush-Larsen gates, forward Euler otherwise, dt
// 0.5 ms) until |dy/dt| < 1e-12 per ms for every state (48 s of model time for the
// clamped variants, 1900 s for active2, whose ions relax with a ~2 min time constant), then
// polished with Newton's method on (V, K_i, Na_i) with r = r_inf(V), s = s_inf(V).
// With dynamic ions the steady states form a one-parameter family (charge
// conservation: K_i + Na_i - C V 1e-3/(F Vol) is invariant), so active2's is the
// one reached from the active1 rest state (K_i 129.4349, Na_i 8.5547 mM: the
// Maleckar/Nygren values used by the Zhang lab).
//   active1 (clamped):   V -48.890 mV (E_K -84.01 mV)
//   active2 (dynamic):   V -47.399 mV, K_i 130.80, Na_i 7.186 mM (E_K -84.29 mV)
//   depolarised:         V -24.004 mV (Kv +30 mV, G_Kv 0.155, clamped)
// MacCannell's -49.6 mV (ELECTRA) uses E_K = -87.33 mV and Ko 5.4 / Nao 140 / Nai
// 9.05 mM / 308 K (Grandi environment); here E_K = -84.0 mV and E_Na = +71.8 mV.
struct RestState {
  double V, r, s, K_i, Na_i;
};
constexpr RestState kRestActive2 = {-47.398641023, 0.0765066772754, 0.970272953697, 130.803662505,
                                    7.18600857714};
constexpr RestState kRestActive1 = {-48.8901027987, 0.067460266402, 0.975839666361, 129.4349,
                                    8.5547};
constexpr RestState kRestDepolarised = {-24.0036402184, 0.0434700452346, 0.988215217905, 129.4349,
                                        8.5547};

class MaleckarActive2 final : public fibrodem::CellModel {
 public:
  MaleckarActive2() {
    info_.name = "maleckar_active2";
    info_.version = "1.0.0";
    info_.description =
        "Active human atrial fibroblast (MacCannell 2007 currents, Maleckar 2009 'active 2' with "
        "dynamic K_i and Na_i).";
    info_.reference =
        "Maleckar MM et al. Biophys J 97:2179-2190 (2009); MacCannell KA et al. Biophys J "
        "92:4121-4132 (2007)";
    info_.kind = fibrodem::ModelKind::ionic;

    info_.states.resize(kNumStates);
    info_.states[kV] = {"V", "mV", kRestActive2.V, -190.0, 200.0, false};
    info_.states[kr] = {"r", "1", kRestActive2.r, 0.0, 1.0, true};
    info_.states[ks] = {"s", "1", kRestActive2.s, 0.0, 1.0, true};
    info_.states[kK_i] = {"K_i", "mM", kRestActive2.K_i, 0.0, 1000.0, false};
    info_.states[kNa_i] = {"Na_i", "mM", kRestActive2.Na_i, 0.0, 1000.0, false};

    info_.parameters.resize(kNumParams);
    auto& p = info_.parameters;
    p[kC_pF] = {"C_pF", "pF", 6.3, "membrane capacitance (MacCannell 2007)"};
    p[kG_Kv] = {"G_Kv", "nS/pF", 0.25, "time-dependent K+ current I_Kv conductance"};
    p[kG_K1] = {"G_K1", "nS/pF", 0.4822, "inward rectifier I_K1 conductance"};
    p[kG_bNa] = {"G_bNa", "nS/pF", 0.0095, "background Na+ conductance"};
    p[kI_NaK_max] = {"I_NaK_max", "pA/pF", 2.002, "Na+/K+ pump maximum"};
    p[kK_mK] = {"K_mK_mM", "mM", 1.0, "I_NaK K_o half-saturation"};
    p[kK_mNa] = {"K_mNa_mM", "mM", 11.0, "I_NaK Na_i half-saturation (Hill 1.5)"};
    p[kV_rev] = {"V_rev_mV", "mV", -150.0, "I_NaK voltage factor (V - V_rev)/(V - B)"};
    p[kB] = {"B_mV", "mV", -200.0, "I_NaK voltage factor pole"};
    p[kKv_shift] = {"Kv_shift_mV", "mV", 0.0,
                    "shift of I_Kv r and s voltage dependence (V -> V - shift)"};
    p[kK_o] = {"K_o_mM", "mM", 5.3581, "extracellular K+ (Maleckar/Nygren)"};
    p[kNa_o] = {"Na_o_mM", "mM", 130.011, "extracellular Na+ (Maleckar/Nygren)"};
    p[kT] = {"T", "K", 306.15, "temperature"};
    p[kR] = {"R", "mJ/mol/K", 8314.0, "gas constant"};
    p[kF] = {"F", "C/mol", 96487.0, "Faraday constant"};
    p[kVol_nL] = {"Vol_nL", "nL", 0.00137, "intracellular volume for K_i, Na_i"};
    p[kDynamic_ions] = {"dynamic_ions", "1", 1.0,
                        "1: K_i, Na_i follow their ODEs ('active 2'); 0: clamped"};
    p[kI_ext_K_fraction] = {"i_ext_K_fraction", "1", 0.0,
                            "fraction of i_ext (stimulus + gap current) carried by K+ in "
                            "dK_i/dt when dynamic_ions = 1 (0: i_ext changes no concentration)"};

    info_.inputs = {{"i_ext", "pA", "stimulus and gap-junction current, + depolarising"}};
    info_.outputs = {
        {"I_ion", "pA", "total ionic current, + outward"},
        {"I_Kv", "pA", "time-dependent K+ current"},
        {"I_K1", "pA", "inward rectifier K+ current"},
        {"I_NaK", "pA", "Na+/K+ pump current"},
        {"I_bNa", "pA", "background Na+ current"},
    };

    fibrodem::VariantInfo active2;
    active2.name = "active2";
    active2.description =
        "default: dynamic K_i and Na_i, as the seed paper's 'active 2' (resting steady state)";
    active2.parameters = {{"dynamic_ions", 1.0}};
    active2.initial_state = {{"V", kRestActive2.V},
                             {"r", kRestActive2.r},
                             {"s", kRestActive2.s},
                             {"K_i", kRestActive2.K_i},
                             {"Na_i", kRestActive2.Na_i}};
    fibrodem::VariantInfo active1;
    active1.name = "active1";
    active1.description =
        "K_i, Na_i clamped at 129.4349 / 8.5547 mM (MacCannell/ELECTRA form; the difference "
        "between Maleckar's 'active 1' and 'active 2' is unverified)";
    active1.parameters = {{"dynamic_ions", 0.0}};
    active1.initial_state = {{"V", kRestActive1.V},
                             {"r", kRestActive1.r},
                             {"s", kRestActive1.s},
                             {"K_i", kRestActive1.K_i},
                             {"Na_i", kRestActive1.Na_i}};
    fibrodem::VariantInfo depol;
    depol.name = "depolarised";
    depol.description =
        "I_Kv gates shifted +30 mV and G_Kv 0.155 nS/pF, ions clamped: rest about -24 mV (the "
        "depolarised MacCannell fibroblast of Sridhar2020/FibroblastMotif, after Jacquemet & "
        "Henriquez 2008; -24.5 mV there with E_K -87 mV)";
    depol.parameters = {{"dynamic_ions", 0.0}, {"Kv_shift_mV", 30.0}, {"G_Kv", 0.155}};
    depol.initial_state = {{"V", kRestDepolarised.V},
                           {"r", kRestDepolarised.r},
                           {"s", kRestDepolarised.s},
                           {"K_i", kRestDepolarised.K_i},
                           {"Na_i", kRestDepolarised.Na_i}};
    info_.variants = {active2, active1, depol};

    info_.voltage_state = kV;
    info_.capacitance_parameter = kC_pF;
  }

  const fibrodem::ModelInfo& info() const override { return info_; }

  void evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const override {
    const double* p = block.params;  // one value per block
    const double C = p[kC_pF];
    const double RTF = p[kR] * p[kT] / p[kF];  // mV (R in mJ/(mol K))
    const double shift = p[kKv_shift];
    const double pump_K = p[kI_NaK_max] * p[kK_o] / (p[kK_o] + p[kK_mK]);
    const double KmNa15 = std::pow(p[kK_mNa], 1.5);
    // pA -> mM/ms for a monovalent ion: 1e-3 / (F Vol).
    const double ion_factor = p[kDynamic_ions] * C * 1e-3 / (p[kF] * p[kVol_nL]);

    // Equations generic in R: lanes of cells (simd::Real) or one cell (double).
    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using R = typename std::decay_t<decltype(cell)>::Real;
      const R V = cell.state(kV);
      const R r = cell.state(kr);
      const R s = cell.state(ks);
      const R K_i = cell.state(kK_i);
      const R Na_i = cell.state(kNa_i);

      const R E_K = RTF * log(p[kK_o] / K_i);
      const R E_Na = RTF * log(p[kNa_o] / Na_i);

      // I_Kv and its gates.
      const R vr = V + 20.0 - shift;
      const R vs = V + 23.0 - shift;
      const R r_inf = 1.0 / (1.0 + exp(-vr / 11.0));
      const R tau_r = 20.3 + 138.0 * exp(-(vr / 25.9) * (vr / 25.9));
      const R s_inf = 1.0 / (1.0 + exp(vs / 7.0));
      const R tau_s = 1574.0 + 5268.0 * exp(-(vs / 22.7) * (vs / 22.7));
      const R I_Kv = p[kG_Kv] * r * s * (V - E_K);

      // I_K1.
      const R dk = V - E_K;
      const R a_K1 = 0.1 / (1.0 + exp(0.06 * (dk - 200.0)));
      const R b_K1 = (3.0 * exp(0.0002 * (dk + 100.0)) + exp(0.1 * (dk - 10.0))) /
                     (1.0 + exp(-0.5 * dk));
      const R I_K1 = p[kG_K1] * a_K1 / (a_K1 + b_K1) * dk;

      // I_NaK.
      const R na15 = pow(Na_i, 1.5);
      const R I_NaK = pump_K * na15 / (na15 + KmNa15) * (V - p[kV_rev]) / (V - p[kB]);

      // I_bNa.
      const R I_bNa = p[kG_bNa] * (V - E_Na);

      const R I_ion_pA = C * (I_Kv + I_K1 + I_NaK + I_bNa);
      const R i_ext = cell.input(kI_ext_pA);
      cell.rate(kV, (i_ext - I_ion_pA) / C);
      cell.gate_inf_tau(kr, r_inf, tau_r);
      cell.gate_inf_tau(ks, s_inf, tau_s);
      cell.rate(kK_i,
                (-(I_Kv + I_K1 - 2.0 * I_NaK) + p[kI_ext_K_fraction] * i_ext / C) * ion_factor);
      cell.rate(kNa_i, -(I_bNa + 3.0 * I_NaK) * ion_factor);

      cell.output(kI_ion_pA, I_ion_pA);
      cell.output(kI_Kv_out, C * I_Kv);
      cell.output(kI_K1_out, C * I_K1);
      cell.output(kI_NaK_out, C * I_NaK);
      cell.output(kI_bNa_out, C * I_bNa);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};

}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(MaleckarActive2)
