// Courtemanche, Ramirez, Nattel 1998 human atrial myocyte (CRN).
//   Courtemanche M, Ramirez RJ, Nattel S. Ionic mechanisms underlying human atrial
//   action potential properties: insights from a mathematical model.
//   Am J Physiol 275:H301-H321 (1998). doi:10.1152/ajpheart.1998.275.1.H301
//
// Transcribed from the CellML model of the Physiome Model Repository
// (courtemanche_ramirez_nattel_1998.cellml, P. Noble / C. Lloyd): same 21 states,
// same initial state, same constants, including the points where the CellML
// differs from the printed paper (as documented in Myokit's curated port
// myokit/models c/courtemanche-1998.mmt, used as a cross-check):
//   - g_CaL 0.12375 (paper 0.1238), i_NaK_max 0.59933874 (paper 0.6),
//     g_Kr 0.029411765, g_Ks 0.12941176, g_bNa 0.0006744375 (more digits);
//   - IKur ui beta = exp((V - 158)/16) (the paper prints the opposite sign; the
//     paper's own tau_ui graph agrees with the CellML).
// Equation numbers below are those of the paper's appendix (pp. H317-H319).
//
// Units: the CellML computes whole-cell currents in pA (Cm * pA/pF), volumes in
// um^3, F in C/mmol, so I[pA] / (Vol[um^3] * F) is in mM/ms. Internally the
// currents are in pA/pF (as in the paper) and multiplied by Cm where needed.
//
// Removable singularities (x/(exp(x)-1) forms: INa alpha_m at -47.13 mV, IKr
// alpha_xr at -14.1 and beta_xr at 3.3328, IKs alpha_xs/beta_xs at 19.9, ICaL
// tau_d at -10, Irel tau_w at 7.9 mV) are rewritten with x_over_expm1() below, which
// is exact at and around the singular point. Note: the CellML's own fallback value
// for beta_xr at V = 3.3328 is 3.7836118e-4 /ms, a digit swap of the true limit
// 7.3898e-5 * 5.1237 = 3.78631e-4 /ms; we use the true limit (continuity). The
// CellML's tau_d fallback 4.579/2 = 2.2895 ms also differs slightly from the limit
// 1/(0.035*6.24*2) = 2.28938 ms; again we use the limit.
//
// Stimulus: the CellML adds i_st only to dV/dt, not to dK_i/dt. Myokit's port adds
// I_stim to dK_i/dt so that K_i stays bounded over long pacing. The parameter
// `i_ext_K_fraction` selects this (0 = CellML, default; 1 = Myokit convention, the
// whole i_ext carried by K+).
#include <cmath>
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {

FIBRODEM_USE_LANE_MATH;

enum State {
  kV,
  kNa_i,
  kK_i,
  kCa_i,
  kCa_up,
  kCa_rel,
  km,
  kh,
  kj,
  koa,
  koi,
  kua,
  kui,
  kxr,
  kxs,
  kd,
  kf,
  kf_Ca,
  ku,
  kv,
  kw,
  kNumStates
};

enum Param {
  kCm_pF,
  kR,
  kT,
  kF,
  kNa_o,
  kK_o,
  kCa_o,
  kV_cell,
  kV_i_frac,
  kV_up_frac,
  kV_rel_frac,
  kg_Na,
  kg_K1,
  kg_to,
  kK_Q10,
  kg_Kur_base,
  kg_Kur_var,
  kg_Kr,
  kg_Ks,
  kg_CaL,
  kE_CaL,
  ktau_f_Ca,
  kKm_f_Ca,
  ki_NaK_max,
  kKm_Na_i,
  kKm_K_o,
  kg_B_Na,
  kg_B_Ca,
  kg_B_K,
  kI_NaCa_max,
  kK_mNa,
  kK_mCa,
  kK_sat,
  kgamma,
  ki_CaP_max,
  kKm_CaP,
  kK_rel,
  ktau_u,
  kFn_c1,
  kFn_c2,
  ktau_tr,
  kI_up_max,
  kK_up,
  kCa_up_max,
  kCMDN_max,
  kTRPN_max,
  kCSQN_max,
  kKm_CMDN,
  kKm_TRPN,
  kTroponin_scale,
  kKm_CSQN,
  ki_ext_K_fraction,
  kNumParams
};

enum Input { kI_ext_pA, kJ_TRPN };

enum Output {
  kI_ion_pA,
  kCa_i_out,
  kI_Na_out,
  kI_CaL_out,
  kI_K1_out,
  kI_to_out,
  kI_Kur_out,
  kI_Kr_out,
  kI_Ks_out,
  kI_NaK_out,
  kI_NaCa_out,
  kI_rel_out,
};

// Equations are generic in R: lanes of cells (simd::Real) or one cell (double).
// Both sides of a select are evaluated and one kept (the other may be inf or NaN).

// x / (exp(x) - 1), with its limit 1 - x/2 at x -> 0. expm1 keeps full relative
// precision for small |x|, so the switch only avoids 0/0 at exactly x = 0.
// (simd.hpp's exprel is the other convention, x / (1 - exp(-x)) = x_over_expm1(-x),
// and switches at |x| < 1e-6; this model keeps its own.)
template <class R>
FIBRODEM_LANE_INLINE R x_over_expm1(const R& x) {
  return select(fabs(x) < 1e-12, 1.0 - 0.5 * x, x / expm1(x));
}

template <class R>
R sigmoid(const R& x) {
  return 1.0 / (1.0 + exp(x));
}

template <class R>
struct AlphaBeta {
  R alpha;
  R beta;
};

// ---- Gates (paper eqs. 29-56, 64-68) -------------------------------------------

// INa m (eq. 29-31): alpha_m = 0.32 (V+47.13) / (1 - exp(-0.1 (V+47.13)))
//                            = 3.2 * x_over_expm1(-0.1 (V+47.13)).
template <class R>
AlphaBeta<R> gate_m(const R& V) {
  return {3.2 * x_over_expm1(R(-0.1 * (V + 47.13))), 0.08 * exp(-V / 11.0)};
}

// INa h (eq. 32); h and j switch form at V = -40 mV (both forms are evaluated, one kept).
template <class R>
AlphaBeta<R> gate_h(const R& V) {
  const auto below = V < -40.0;
  return {select(below, 0.135 * exp((V + 80.0) / -6.8), 0.0),
          select(below, 3.56 * exp(0.079 * V) + 3.1e5 * exp(0.35 * V),
                 1.0 / (0.13 * (1.0 + exp((V + 10.66) / -11.1))))};
}

// INa j (eq. 33).
template <class R>
AlphaBeta<R> gate_j(const R& V) {
  const auto below = V < -40.0;
  return {select(below,
                 (-1.2714e5 * exp(0.2444 * V) - 3.474e-5 * exp(-0.04391 * V)) * (V + 37.78) /
                     (1.0 + exp(0.311 * (V + 79.23))),
                 0.0),
          select(below, 0.1212 * exp(-0.01052 * V) / (1.0 + exp(-0.1378 * (V + 40.14))),
                 0.3 * exp(-2.535e-7 * V) / (1.0 + exp(-0.1 * (V + 32.0))))};
}

// Ito oa (eq. 36-37); also IKur ua rates (eq. 42-43). tau divided by KQ10.
template <class R>
R rate_alpha_a(const R& V) {
  return 0.65 / (exp((V + 10.0) / -8.5) + exp((V - 30.0) / -59.0));
}
template <class R>
R rate_beta_a(const R& V) {
  return 0.65 / (2.5 + exp((V + 82.0) / 17.0));
}

// ---- Currents, pA/pF -------------------------------------------------------------

template <class R>
R E_nernst(double RTF_z, double out, const R& in) {
  return RTF_z * log(out / in);
}

class Courtemanche1998 final : public fibrodem::CellModel {
 public:
  Courtemanche1998() {
    info_.name = "courtemanche";
    info_.version = "1.0.0";
    info_.description =
        "Courtemanche-Ramirez-Nattel 1998 human atrial myocyte (CellML constants and initial "
        "state); variant courtemanche1999_caf: the chronic-AF remodelling of Courtemanche et al. 1999.";
    info_.reference =
        "Courtemanche M, Ramirez RJ, Nattel S. Am J Physiol 275:H301-H321 (1998); CellML "
        "courtemanche_ramirez_nattel_1998 (Physiome Model Repository); Courtemanche M, Ramirez RJ, "
        "Nattel S. Cardiovasc Res 42:477-489 (1999)";
    info_.kind = fibrodem::ModelKind::ionic;

    const double g0 = 0.0, g1 = 1.0;
    // Initial values: the CellML file's.
    info_.states.resize(kNumStates);
    info_.states[kV] = {"V", "mV", -81.18, -250.0, 250.0, false};
    info_.states[kNa_i] = {"Na_i", "mM", 11.17, 0.0, 1000.0, false};
    info_.states[kK_i] = {"K_i", "mM", 139.0, 0.0, 1000.0, false};
    info_.states[kCa_i] = {"Ca_i", "mM", 1.013e-4, 0.0, 100.0, false};
    info_.states[kCa_up] = {"Ca_up", "mM", 1.488, 0.0, 1000.0, false};
    info_.states[kCa_rel] = {"Ca_rel", "mM", 1.488, 0.0, 1000.0, false};
    info_.states[km] = {"m", "1", 2.908e-3, g0, g1, true};
    info_.states[kh] = {"h", "1", 9.649e-1, g0, g1, true};
    info_.states[kj] = {"j", "1", 9.775e-1, g0, g1, true};
    info_.states[koa] = {"oa", "1", 3.043e-2, g0, g1, true};
    info_.states[koi] = {"oi", "1", 9.992e-1, g0, g1, true};
    info_.states[kua] = {"ua", "1", 4.966e-3, g0, g1, true};
    info_.states[kui] = {"ui", "1", 9.986e-1, g0, g1, true};
    info_.states[kxr] = {"xr", "1", 3.296e-5, g0, g1, true};
    info_.states[kxs] = {"xs", "1", 1.869e-2, g0, g1, true};
    info_.states[kd] = {"d", "1", 1.367e-4, g0, g1, true};
    info_.states[kf] = {"f", "1", 9.996e-1, g0, g1, true};
    info_.states[kf_Ca] = {"f_Ca", "1", 7.755e-1, g0, g1, true};
    info_.states[ku] = {"u", "1", 2.35e-112, g0, g1, true};
    info_.states[kv] = {"v", "1", 1.0, g0, g1, true};
    info_.states[kw] = {"w", "1", 0.9992, g0, g1, true};
    // Gates whose rates depend only on V (f_Ca on Ca_i, u and v on the release
    // flux Fn; w's rates are V-only too but stay with u, v in the release block).
    for (int k : {km, kh, kj, koa, koi, kua, kui, kxr, kxs, kd, kf}) info_.states[k].voltage_only = true;

    info_.parameters.resize(kNumParams);
    auto& p = info_.parameters;
    p[kCm_pF] = {"Cm_pF", "pF", 100.0, "membrane capacitance (Table 1)"};
    p[kR] = {"R", "J/mol/K", 8.3143, "gas constant"};
    p[kT] = {"T", "K", 310.0, "temperature"};
    p[kF] = {"F", "C/mmol", 96.4867, "Faraday constant"};
    p[kNa_o] = {"Na_o_mM", "mM", 140.0, "extracellular Na+"};
    p[kK_o] = {"K_o_mM", "mM", 5.4, "extracellular K+"};
    p[kCa_o] = {"Ca_o_mM", "mM", 1.8, "extracellular Ca2+"};
    p[kV_cell] = {"V_cell_um3", "um^3", 20100.0, "cell volume"};
    p[kV_i_frac] = {"V_i_fraction", "1", 0.68, "cytosolic volume / V_cell"};
    p[kV_up_frac] = {"V_up_fraction", "1", 0.0552, "NSR (uptake) volume / V_cell"};
    p[kV_rel_frac] = {"V_rel_fraction", "1", 0.0048, "JSR (release) volume / V_cell"};
    p[kg_Na] = {"g_Na", "nS/pF", 7.8, "INa maximal conductance"};
    p[kg_K1] = {"g_K1", "nS/pF", 0.09, "IK1 maximal conductance"};
    p[kg_to] = {"g_to", "nS/pF", 0.1652, "Ito maximal conductance"};
    p[kK_Q10] = {"K_Q10", "1", 3.0, "temperature factor dividing Ito and IKur gate taus"};
    p[kg_Kur_base] = {"g_Kur_base", "nS/pF", 0.005,
                      "IKur conductance: g = base + var/(1+exp((V-15)/-13)) (eq. 41)"};
    p[kg_Kur_var] = {"g_Kur_var", "nS/pF", 0.05, "IKur voltage-dependent conductance part"};
    p[kg_Kr] = {"g_Kr", "nS/pF", 0.029411765, "IKr maximal conductance"};
    p[kg_Ks] = {"g_Ks", "nS/pF", 0.12941176, "IKs maximal conductance"};
    p[kg_CaL] = {"g_CaL", "nS/pF", 0.12375, "ICaL maximal conductance"};
    p[kE_CaL] = {"E_CaL_mV", "mV", 65.0, "ICaL apparent reversal potential"};
    p[ktau_f_Ca] = {"tau_f_Ca_ms", "ms", 2.0, "ICaL Ca-inactivation time constant"};
    p[kKm_f_Ca] = {"Km_f_Ca_mM", "mM", 0.00035, "ICaL Ca-inactivation half-saturation"};
    p[ki_NaK_max] = {"i_NaK_max", "pA/pF", 0.59933874, "INaK maximum"};
    p[kKm_Na_i] = {"Km_Na_i_mM", "mM", 10.0, "INaK Na_i half-saturation"};
    p[kKm_K_o] = {"Km_K_o_mM", "mM", 1.5, "INaK K_o half-saturation"};
    p[kg_B_Na] = {"g_B_Na", "nS/pF", 0.0006744375, "background Na+ conductance"};
    p[kg_B_Ca] = {"g_B_Ca", "nS/pF", 0.001131, "background Ca2+ conductance"};
    p[kg_B_K] = {"g_B_K", "nS/pF", 0.0,
                 "background K+ conductance (CellML: 0; used in dK_i and, here, also dV)"};
    p[kI_NaCa_max] = {"I_NaCa_max", "pA/pF", 1600.0, "INaCa maximum"};
    p[kK_mNa] = {"K_mNa_mM", "mM", 87.5, "INaCa Na half-saturation"};
    p[kK_mCa] = {"K_mCa_mM", "mM", 1.38, "INaCa Ca half-saturation"};
    p[kK_sat] = {"K_sat", "1", 0.1, "INaCa saturation factor"};
    p[kgamma] = {"gamma", "1", 0.35, "INaCa voltage-dependence parameter"};
    p[ki_CaP_max] = {"i_CaP_max", "pA/pF", 0.275, "sarcolemmal Ca pump maximum"};
    p[kKm_CaP] = {"Km_CaP_mM", "mM", 0.0005, "sarcolemmal Ca pump half-saturation"};
    p[kK_rel] = {"K_rel", "1/ms", 30.0, "maximal JSR release rate"};
    p[ktau_u] = {"tau_u_ms", "ms", 8.0, "release activation gate u time constant"};
    p[kFn_c1] = {"Fn_half", "umol/ms", 3.4175e-13,
                 "Fn threshold of u_inf (v_inf uses 0.2 * Fn_half)"};
    p[kFn_c2] = {"Fn_slope", "umol/ms", 13.67e-16, "Fn slope factor of u_inf, v_inf"};
    p[ktau_tr] = {"tau_tr_ms", "ms", 180.0, "NSR -> JSR transfer time constant"};
    p[kI_up_max] = {"I_up_max", "mM/ms", 0.005, "maximal SR uptake rate"};
    p[kK_up] = {"K_up_mM", "mM", 0.00092, "SR uptake half-saturation"};
    p[kCa_up_max] = {"Ca_up_max_mM", "mM", 15.0, "maximal NSR Ca2+"};
    p[kCMDN_max] = {"CMDN_max_mM", "mM", 0.05, "total calmodulin"};
    p[kTRPN_max] = {"TRPN_max_mM", "mM", 0.07, "total troponin"};
    p[kCSQN_max] = {"CSQN_max_mM", "mM", 10.0, "total calsequestrin"};
    p[kKm_CMDN] = {"Km_CMDN_mM", "mM", 0.00238, "calmodulin half-saturation"};
    p[kKm_TRPN] = {"Km_TRPN_mM", "mM", 0.0005, "troponin half-saturation"};
    p[kTroponin_scale] = {"troponin_buffer_scale", "1", 1.0,
                          "scale of CRN's own troponin buffer (fibrodem sets 0 with calcium_feedback)"};
    p[kKm_CSQN] = {"Km_CSQN_mM", "mM", 0.8, "calsequestrin half-saturation"};
    p[ki_ext_K_fraction] = {"i_ext_K_fraction", "1", 0.0,
                            "fraction of i_ext carried by K+ in dK_i/dt (0 = CellML; 1 = Myokit "
                            "port, keeps K_i bounded under long pacing)"};

    info_.inputs = {{"i_ext", "pA", "stimulus and gap-junction current, + depolarising"},
                    {"J_TRPN", "mM/ms", "Ca binding flux to a myofilament model's troponin (calcium feedback)"}};
    info_.outputs = {
        {"I_ion", "pA", "total ionic current, + outward"},
        {"Ca_i", "mM", "bulk cytosolic Ca2+"},
        {"I_Na", "pA", "fast Na+ current"},
        {"I_CaL", "pA", "L-type Ca2+ current"},
        {"I_K1", "pA", "inward rectifier K+ current"},
        {"I_to", "pA", "transient outward K+ current"},
        {"I_Kur", "pA", "ultrarapid delayed rectifier K+ current"},
        {"I_Kr", "pA", "rapid delayed rectifier K+ current"},
        {"I_Ks", "pA", "slow delayed rectifier K+ current"},
        {"I_NaK", "pA", "Na+/K+ pump current"},
        {"I_NaCa", "pA", "Na+/Ca2+ exchanger current"},
        {"J_rel", "mM/ms", "JSR Ca2+ release flux"},
    };
    // Variants. The first is the default: the CellML's initial state.
    fibrodem::VariantInfo cellml;
    cellml.name = "cellml";
    cellml.description = "CellML constants and initial state (V -81.18 mV, Na_i 11.17 mM)";
    // The state just before the 99th stimulus of 1 Hz pacing from the CellML initial
    // state (2000 pA x 2 ms at the start of each 1000 ms cycle, i_ext_K_fraction 0),
    // computed offline with a throwaway single-cell driver (Rush-Larsen for gates,
    // forward Euler otherwise, dt 0.005 ms). This is the pacing history of the
    // reference trace Original_CRN_Model.dat (HaiboNi/updated_cnz_for_ina_ikur_block_study,
    // whose beat starts at t = 98000 ms). Na_i keeps drifting (~+0.008 mM per beat).
    fibrodem::VariantInfo paced;
    paced.name = "paced_1hz";
    paced.description =
        "CellML model, initial state after 98 beats at 1 Hz (2000 pA x 2 ms) from the CellML "
        "state";
    paced.initial_state = {
        {"V", -81.14744731},    {"Na_i", 12.17387961},
        {"K_i", 137.6878097},   {"Ca_i", 0.0001186822115},
        {"Ca_up", 1.583495618}, {"Ca_rel", 1.163160598},
        {"m", 0.002924412514},  {"h", 0.9646223446},
        {"j", 0.9771661994},    {"oa", 0.03049373624},
        {"oi", 0.9992359577},   {"ua", 0.004984584116},
        {"ui", 0.9896994464},   {"xr", 0.001523257756},
        {"xs", 0.01938122747},  {"d", 0.0001372762784},
        {"f", 0.9269593638},    {"f_Ca", 0.746647197},
        {"u", 3.854472816e-53}, {"v", 1.0},
        {"w", 0.999196963},
    };
    // Chronic-AF ionic remodelling of Courtemanche, Ramirez, Nattel 1999 (Cardiovasc Res
    // 42:477, "Ionic targets for drug therapy and atrial fibrillation-induced electrical
    // remodeling"): I_to -50 %, I_CaL -70 %, I_Kur -50 % (the paper's combined cAF set,
    // from the current densities measured in cAF patients' myocytes; both parts of
    // g_Kur scaled). Its initial state: the state before the 301st stimulus of 300
    // cAF beats at 1 Hz (2000 pA x 2 ms, Rush-Larsen, dt 0.005 ms) from the paced_1hz
    // state; like the control model, Na_i and K_i keep drifting (APD90 192.7 ms at
    // beat 300, changing by ~0.006 ms a beat).
    fibrodem::VariantInfo caf;
    caf.name = "courtemanche1999_caf";
    caf.description =
        "Courtemanche et al. 1999 chronic-AF remodelling: g_to x0.5, g_CaL x0.3, g_Kur x0.5; initial "
        "state after 300 beats at 1 Hz from paced_1hz";
    caf.parameters = {
        {"g_to", 0.5 * p[kg_to].default_value},
        {"g_CaL", 0.3 * p[kg_CaL].default_value},
        {"g_Kur_base", 0.5 * p[kg_Kur_base].default_value},
        {"g_Kur_var", 0.5 * p[kg_Kur_var].default_value},
    };
    caf.initial_state = {
        {"V", -81.59372587},  {"Na_i", 12.17931133},  {"K_i", 136.8422254},  {"Ca_i", 9.545524702e-05},
        {"Ca_up", 1.226337335},  {"Ca_rel", 0.9288224899},  {"m", 0.002717292614},
        {"h", 0.9679316157},  {"j", 0.9795406029},  {"oa", 0.02974892119},  {"oi", 0.9992985233},
        {"ua", 0.00475879112},  {"ui", 0.990854801},  {"xr", 0.000527549067},  {"xs", 0.01864481449},
        {"d", 0.0001298259315},  {"f", 0.9678299918},  {"f_Ca", 0.7856354733},  {"u", 2.981780279e-53},
        {"v", 1.0},  {"w", 0.9992177588},
    };
    info_.variants = {cellml, paced, caf};

    info_.voltage_state = kV;
    info_.capacitance_parameter = kCm_pF;
  }

  const fibrodem::ModelInfo& info() const override { return info_; }

  void evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const override {
    const double* p = block.params;  // one value per block
    const double Cm = p[kCm_pF];
    const double RTF = p[kR] * p[kT] / p[kF];  // mV
    const double FRT = 1.0 / RTF;
    const double V_i = p[kV_cell] * p[kV_i_frac];
    const double V_up = p[kV_cell] * p[kV_up_frac];
    const double V_rel = p[kV_cell] * p[kV_rel_frac];
    const double KQ10 = p[kK_Q10];
    // INaK [Na]o dependence (eq. 58) and INaCa denominator constant (eq. 60).
    const double sigma = (std::exp(p[kNa_o] / 67.3) - 1.0) / 7.0;
    const double naca_den =
        (std::pow(p[kK_mNa], 3) + std::pow(p[kNa_o], 3)) * (p[kK_mCa] + p[kCa_o]);
    const double Nao3 = std::pow(p[kNa_o], 3);

    fibrodem::for_each_lane_group(block, [&](const auto& cell) {
      using R = typename std::decay_t<decltype(cell)>::Real;
      const R V = cell.state(kV);
      const R Na_i = cell.state(kNa_i);
      const R K_i = cell.state(kK_i);
      const R Ca_i = cell.state(kCa_i);
      const R Ca_up = cell.state(kCa_up);
      const R Ca_rel = cell.state(kCa_rel);
      const R m = cell.state(km), h = cell.state(kh), j = cell.state(kj);
      const R oa = cell.state(koa), oi = cell.state(koi);
      const R ua = cell.state(kua), ui = cell.state(kui);
      const R xr = cell.state(kxr), xs = cell.state(kxs);
      const R d = cell.state(kd), f = cell.state(kf), f_Ca = cell.state(kf_Ca);
      const R u = cell.state(ku), v = cell.state(kv), w = cell.state(kw);

      // Reversal potentials (eq. 28).
      const R E_Na = E_nernst(RTF, p[kNa_o], Na_i);
      const R E_K = E_nernst(RTF, p[kK_o], K_i);
      const R E_Ca = E_nernst(0.5 * RTF, p[kCa_o], Ca_i);

      // ---- Currents in pA/pF ----
      // INa (eq. 29).
      const R i_Na = p[kg_Na] * m * m * m * h * j * (V - E_Na);
      // IK1 (eq. 35).
      const R i_K1 = p[kg_K1] * (V - E_K) / (1.0 + exp(0.07 * (V + 80.0)));
      // Ito (eq. 36).
      const R i_to = p[kg_to] * oa * oa * oa * oi * (V - E_K);
      // IKur (eq. 41).
      const R g_Kur = p[kg_Kur_base] + p[kg_Kur_var] / (1.0 + exp((V - 15.0) / -13.0));
      const R i_Kur = g_Kur * ua * ua * ua * ui * (V - E_K);
      // IKr (eq. 47).
      const R i_Kr = p[kg_Kr] * xr * (V - E_K) / (1.0 + exp((V + 15.0) / 22.4));
      // IKs (eq. 50).
      const R i_Ks = p[kg_Ks] * xs * xs * (V - E_K);
      // ICaL (eq. 53).
      const R i_CaL = p[kg_CaL] * d * f * f_Ca * (V - p[kE_CaL]);
      // INaK (eq. 57-59).
      const R f_NaK =
          1.0 / (1.0 + 0.1245 * exp(-0.1 * V * FRT) + 0.0365 * sigma * exp(-V * FRT));
      const R i_NaK = p[ki_NaK_max] * f_NaK / (1.0 + pow(p[kKm_Na_i] / Na_i, 1.5)) *
                      p[kK_o] / (p[kK_o] + p[kKm_K_o]);
      // INaCa (eq. 60).
      const double gam = p[kgamma];
      const R i_NaCa = p[kI_NaCa_max] *
                       (exp(gam * V * FRT) * Na_i * Na_i * Na_i * p[kCa_o] -
                        exp((gam - 1.0) * V * FRT) * Nao3 * Ca_i) /
                       (naca_den * (1.0 + p[kK_sat] * exp((gam - 1.0) * V * FRT)));
      // Background currents (eq. 61-62), IpCa (eq. 63).
      const R i_B_Na = p[kg_B_Na] * (V - E_Na);
      const R i_B_Ca = p[kg_B_Ca] * (V - E_Ca);
      const R i_B_K = p[kg_B_K] * (V - E_K);
      const R i_CaP = p[ki_CaP_max] * Ca_i / (p[kKm_CaP] + Ca_i);

      // ---- Ca handling, mM/ms (eq. 64-72) ----
      const R i_rel = p[kK_rel] * u * u * v * w * (Ca_rel - Ca_i);
      const R i_tr = (Ca_up - Ca_rel) / p[ktau_tr];
      const R i_up = p[kI_up_max] / (1.0 + p[kK_up] / Ca_i);
      const R i_up_leak = p[kI_up_max] * Ca_up / p[kCa_up_max];
      // Fn (eq. 68), CellML units: currents in pA, volumes in um^3.
      const R Fn =
          1e3 * (1e-15 * V_rel * i_rel - 1e-15 / (2.0 * p[kF]) * (0.5 * i_CaL - 0.2 * i_NaCa) * Cm);

      // ---- Membrane ----
      const R i_ion = i_Na + i_K1 + i_to + i_Kur + i_Kr + i_Ks + i_B_Na + i_B_Ca + i_B_K +
                      i_NaK + i_CaP + i_NaCa + i_CaL;  // pA/pF
      const R I_ion_pA = Cm * i_ion;
      const R i_ext = cell.input(kI_ext_pA);
      cell.rate(kV, (i_ext - I_ion_pA) / Cm);

      // ---- Concentrations (eq. 21-27) ----
      const double FVi = p[kF] * V_i;
      cell.rate(kNa_i, Cm * (-3.0 * i_NaK - (3.0 * i_NaCa + i_B_Na + i_Na)) / FVi);
      cell.rate(kK_i, (Cm * (2.0 * i_NaK - (i_K1 + i_to + i_Kur + i_Kr + i_Ks + i_B_K)) +
                       p[ki_ext_K_fraction] * i_ext) /
                          FVi);
      const R B1 = Cm * (2.0 * i_NaCa - (i_CaP + i_CaL + i_B_Ca)) / (2.0 * FVi) +
                   (V_up * (i_up_leak - i_up) + i_rel * V_rel) / V_i;
      const R kt = Ca_i + p[kKm_TRPN], kc = Ca_i + p[kKm_CMDN];
      // Troponin: CRN's rapid-equilibrium buffer, scaled by troponin_buffer_scale
      // (0 when a myofilament model owns troponin and feeds its binding flux
      // J_TRPN back: fibrodem's calcium_feedback).
      const double TRPN_max = p[kTRPN_max] * p[kTroponin_scale];
      const R B2 = 1.0 + TRPN_max * p[kKm_TRPN] / (kt * kt) + p[kCMDN_max] * p[kKm_CMDN] / (kc * kc);
      cell.rate(kCa_i, (B1 - cell.input(kJ_TRPN)) / B2);
      cell.rate(kCa_up, i_up - (i_up_leak + i_tr * V_rel / V_up));
      const R kq = Ca_rel + p[kKm_CSQN];
      cell.rate(kCa_rel, (i_tr - i_rel) / (1.0 + p[kCSQN_max] * p[kKm_CSQN] / (kq * kq)));

      // ---- Gates ----
      // Gates marked voltage_only may be left to the core's lookup table.
      if (!block.skip_voltage_only_gates) {
        const auto gm = gate_m(V);
        cell.gate_alpha_beta(km, gm.alpha, gm.beta);
        const auto gh = gate_h(V);
        cell.gate_alpha_beta(kh, gh.alpha, gh.beta);
        const auto gj = gate_j(V);
        cell.gate_alpha_beta(kj, gj.alpha, gj.beta);

        // Ito oa, oi (eq. 37-40).
        const R tau_a = 1.0 / ((rate_alpha_a(V) + rate_beta_a(V)) * KQ10);
        cell.gate_inf_tau(koa, sigmoid(R((V + 20.47) / -17.54)), tau_a);
        {
          const R a_oi = 1.0 / (18.53 + exp((V + 113.7) / 10.95));
          const R b_oi = 1.0 / (35.56 + exp((V + 1.26) / -7.44));
          cell.gate_inf_tau(koi, sigmoid(R((V + 43.1) / 5.3)), 1.0 / ((a_oi + b_oi) * KQ10));
        }
        // IKur ua, ui (eq. 42-46); ui beta as in the CellML: exp((V - 158)/16).
        cell.gate_inf_tau(kua, sigmoid(R((V + 30.3) / -9.6)), tau_a);
        {
          const R a_ui = 1.0 / (21.0 + exp((V - 185.0) / -28.0));
          const R b_ui = exp((V - 158.0) / 16.0);
          cell.gate_inf_tau(kui, sigmoid(R((V - 99.45) / 27.48)), 1.0 / ((a_ui + b_ui) * KQ10));
        }
        // IKr xr (eq. 48-49): alpha = 0.0003 (V+14.1)/(1-exp(-(V+14.1)/5)) = 0.0015
        // x_over_expm1(-(V+14.1)/5); beta = 7.3898e-5 (V-3.3328)/(exp((V-3.3328)/5.1237)-1)
        // = 7.3898e-5*5.1237 x_over_expm1(...).
        {
          const R a_xr = 0.0003 * 5.0 * x_over_expm1(R(-(V + 14.1) / 5.0));
          const R b_xr = 7.3898e-5 * 5.1237 * x_over_expm1(R((V - 3.3328) / 5.1237));
          cell.gate_inf_tau(kxr, sigmoid(R((V + 14.1) / -6.5)), 1.0 / (a_xr + b_xr));
        }
        // IKs xs (eq. 51-52): alpha = 4e-5*17 x_over_expm1(-(V-19.9)/17), beta = 3.5e-5*9
        // x_over_expm1((V-19.9)/9).
        {
          const R a_xs = 4e-5 * 17.0 * x_over_expm1(R(-(V - 19.9) / 17.0));
          const R b_xs = 3.5e-5 * 9.0 * x_over_expm1(R((V - 19.9) / 9.0));
          const R xs_inf = 1.0 / sqrt(1.0 + exp((V - 19.9) / -12.7));
          cell.gate_inf_tau(kxs, xs_inf, 0.5 / (a_xs + b_xs));
        }
        // ICaL d (eq. 54): tau_d = (1-e^{-x})/(0.035*6.24 x (1+e^{-x})), x = (V+10)/6.24,
        // and (1-e^{-x})/x = 1/x_over_expm1(-x).
        {
          const R x = (V + 10.0) / 6.24;
          const R tau_d = 1.0 / (0.035 * 6.24 * x_over_expm1(R(-x)) * (1.0 + exp(-x)));
          cell.gate_inf_tau(kd, sigmoid(R((V + 10.0) / -8.0)), tau_d);
        }
        // ICaL f (eq. 55), f_Ca (eq. 56).
        {
          const R dv = V + 10.0;
          const R tau_f = 9.0 / (0.0197 * exp(-0.0337 * 0.0337 * dv * dv) + 0.02);
          cell.gate_inf_tau(kf, sigmoid(R((V + 28.0) / 6.9)), tau_f);
        }
      }  // voltage_only gates
      cell.gate_inf_tau(kf_Ca, 1.0 / (1.0 + Ca_i / p[kKm_f_Ca]), R(p[ktau_f_Ca]));
      // Irel u, v, w (eq. 64-67).
      {
        const double c1 = p[kFn_c1], c2 = p[kFn_c2];
        const R s_u = 1.0 / (1.0 + exp(-(Fn - c1) / c2));
        cell.gate_inf_tau(ku, s_u, R(p[ktau_u]));
        const R v_inf = 1.0 - 1.0 / (1.0 + exp(-(Fn - 0.2 * c1) / c2));
        cell.gate_inf_tau(kv, v_inf, 1.91 + 2.09 * s_u);
        // tau_w = 6 (1-e^{-x}) / ((1+0.3 e^{-x}) 5 x), x = (V-7.9)/5.
        const R x = (V - 7.9) / 5.0;
        const R tau_w = 6.0 / (5.0 * x_over_expm1(R(-x)) * (1.0 + 0.3 * exp(-x)));
        const R w_inf = 1.0 - 1.0 / (1.0 + exp(-(V - 40.0) / 17.0));
        cell.gate_inf_tau(kw, w_inf, tau_w);
      }

      cell.output(kI_ion_pA, I_ion_pA);
      cell.output(kCa_i_out, Ca_i);
      cell.output(kI_Na_out, Cm * i_Na);
      cell.output(kI_CaL_out, Cm * i_CaL);
      cell.output(kI_K1_out, Cm * i_K1);
      cell.output(kI_to_out, Cm * i_to);
      cell.output(kI_Kur_out, Cm * i_Kur);
      cell.output(kI_Kr_out, Cm * i_Kr);
      cell.output(kI_Ks_out, Cm * i_Ks);
      cell.output(kI_NaK_out, Cm * i_NaK);
      cell.output(kI_NaCa_out, Cm * i_NaCa);
      cell.output(kI_rel_out, i_rel);
    });
  }

 private:
  fibrodem::ModelInfo info_;
};

}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Courtemanche1998)
