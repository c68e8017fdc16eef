// Colman et al. 2013 human atrial myocyte, right atrium, in two parameter sets.
//
//   Colman MA, Aslanidi OV, Kharche S, Boyett MR, Garratt C, Hancox JC, Zhang H.
//   J Physiol 591:4249-4272 (2013): Courtemanche-Ramirez-Nattel 1998 (CRN) with
//   Maleckar 2009 I_to and I_Kur and a simplified Koivumaki 2011 Ca system
//   (junctional subspace Ca_ss + bulk Ca_i, two SR compartments, 2-state SERCA,
//   RyR o/c/a gates per compartment).
//   Ni H, Whittaker DG, Wang W, Giles WR, Narayan SM, Zhang H. Front Physiol 8:946
//   (2017): the "updated CNZ" model (new I_Kur, scaled currents, faster RyR).
//
// Equations are transcribed from the Myokit port of Ni 2017 (myokit/models
// c/ni-2017.mmt, M. Clerx, checked against the authors' C++; CellML export
// ni_2017.cellml), with the same units: ms, mV, pA, pF, nS/pF, mM, um^3.
// Every Colman-2013 / Ni-2017 difference is a parameter or a switch; the two
// variants are parameter sets:
//   colman2013 (default): the original Colman model as in the authors' committed
//     1 Hz trace (Original_Colman_Model.dat); values and reasons beside the variant
//     table at the end of this file.
//   ni2017: Ni 2017 exactly as ni-2017.mmt (RA, not AF), including its quirks:
//     G1 I_to time constants use exp(-(x)*2) instead of exp(-x^2);
//     G2 the SR Ca equations carry a factor 1000 (a ms/s slip of the C++ code);
//     K_i is constant (dK_i/dt = 0).
//   The 4 drug-binding states of ni-2017.mmt (ina.BA, ina.BI, ikur.BO, ikur.BC)
//   are left out: with no drug (ina.drug_concen = 0; acacetin 1e-14 uM) they stay
//   at 0 (BO, BC ~ 1e-16) and the acacetin factors differ from 1 by < 1e-12.
//
// Conventions (fibrodem): inputs[0] i_ext [pA, + depolarising]; dV/dt =
// (i_ext - I_ion)/Cm; outputs[0] I_ion [pA, + outward], outputs[1] Ca_i [mM].
// K_i is constant in both published codes, so i_ext enters no concentration.
// Gates (including the RyR o/c/a gates, whose steady states depend on Ca and on
// the a gate) are returned as y_inf/tau for Rush-Larsen; x/(1 - exp(-x)) forms
// use their analytic limit near 0 (exprel below).
#include <cmath>
#include <string>
#include <type_traits>

#include "model/block_access.hpp"
#include "model/cell_model.hpp"

namespace {


// ---------------------------------------------------------------------------
// States: name, unit, initial value (colman2013), lower, upper, gate.
// Initial values: 1 Hz steady state of the colman2013 variant (see the variant
// table at the end of the file for how they were obtained).
#define COLMAN_STATES(X)                              \
  X(V, "mV", -75.09824041, -250.0, 250.0, false)      \
  X(m, "1", 0.007816811521, 0.0, 1.0, true)           \
  X(h, "1", 0.8744402186, 0.0, 1.0, true)             \
  X(j, "1", 0.8971746462, 0.0, 1.0, true)             \
  X(d, "1", 0.0002923393588, 0.0, 1.0, true)          \
  X(f, "1", 0.958954801, 0.0, 1.0, true)              \
  X(fca, "1", 0.7127426043, 0.0, 1.0, true)           \
  X(xr, "1", 0.001227455208, 0.0, 1.0, true)          \
  X(xs, "1", 0.0240430583, 0.0, 1.0, true)            \
  X(ito_r, "1", 0.008581987611, 0.0, 1.0, true)       \
  X(ito_s, "1", 0.9088986589, 0.0, 1.0, true)         \
  X(ikur_a, "1", 0.0003237758026, 0.0, 1.0, true)     \
  X(ikur_i, "1", 0.9602150173, 0.0, 1.0, true)        \
  X(Na_i, "mM", 11.17, 0.0, 1000.0, false)            \
  X(K_i, "mM", 114.76, 0.0, 1000.0, false)            \
  X(Ca_i, "mM", 0.0001622200375, 0.0, 100.0, false)   \
  X(Ca_ss, "mM", 0.0001410535334, 0.0, 100.0, false)  \
  X(Ca_SRi, "mM", 0.9995985807, 0.0, 100.0, false)    \
  X(Ca_SRss, "mM", 0.9969855257, 0.0, 100.0, false)   \
  X(SERCACa, "mM", 0.009755059981, 0.0, 1.0, false)   \
  X(SERCACass, "mM", 0.009581561724, 0.0, 1.0, false) \
  X(ryr_o_ss, "1", 9.542539893e-05, 0.0, 1.0, true)   \
  X(ryr_c_ss, "1", 0.9996009092, 0.0, 1.0, true)      \
  X(ryr_a_ss, "1", 0.1984794761, 0.0, 1.0, true)      \
  X(ryr_o_i, "1", 0.000149377548, 0.0, 1.0, true)     \
  X(ryr_c_i, "1", 0.9985239234, 0.0, 1.0, true)       \
  X(ryr_a_i, "1", 0.205705063, 0.0, 1.0, true)

// ---------------------------------------------------------------------------
// Parameters: name, unit, default (= colman2013 value), description.
#define COLMAN_PARAMS(X)                                                                                      \
  /* physical constants, geometry, external ions (CRN 1998 / Koivumaki 2011 via ni-2017.mmt) */               \
  X(Cm_pF, "pF", 100.0, "membrane capacitance")                                                               \
  X(T_K, "K", 310.0, "temperature")                                                                           \
  X(F_C_per_mmol, "C/mmol", 96.4867, "Faraday constant")                                                      \
  X(R_J_per_mol_K, "J/mol/K", 8.3143, "gas constant")                                                         \
  X(nernst_mono_mV, "mV", 26.71, "RT/F used for E_Na and E_K (the code's literal 26.71)")                     \
  X(nernst_Ca_mV, "mV", 13.35, "RT/2F used for E_Ca (the code's literal 13.35)")                              \
  X(Vi_um3, "um^3", 13668.0, "cytosolic volume for Na_i (CRN)")                                               \
  X(Vss_um3, "um^3", 2.0 * 49.9232, "junctional subspace volume (Koivumaki x2 for 100 pF)")                   \
  X(Vnj_um3, "um^3", 6.0 * 2531.0, "bulk (non-junctional) Ca volume (Koivumaki x6)")                          \
  X(VSRi_um3, "um^3", 2.0 * 57.0, "bulk SR volume (Koivumaki x2)")                                            \
  X(VSRss_um3, "um^3", 2.0 * 80.0, "junctional SR volume (Koivumaki x2)")                                     \
  X(dx_um, "um", 1.625, "Ca diffusion grid spacing (Koivumaki)")                                              \
  X(Aj_nj_um2, "um^2", 2492.324412, "junctional/non-junctional interface area (Koivumaki)")                   \
  X(xj_nj_um, "um", 0.8225, "junctional to non-junctional diffusion distance (Koivumaki)")                    \
  X(Na_o_mM, "mM", 140.0, "extracellular Na")                                                                 \
  X(Ca_o_mM, "mM", 1.8, "extracellular Ca")                                                                   \
  X(K_o_mM, "mM", 5.4, "extracellular K")                                                                     \
  /* I_Na (CRN) */                                                                                            \
  X(g_Na_nS_per_pF, "nS/pF", 7.8, "I_Na conductance (CRN)")                                                   \
  X(g_Na_scale, "1", 1.0, "regional/AF scale of g_Na")                                                        \
  X(INa_m_shift_mV, "mV", 0.0, "I_Na activation shift (Ni AF: +1.6 mV)")                                      \
  /* I_to (Maleckar 2009 r/s) */                                                                              \
  X(g_to_nS_per_pF, "nS/pF", 0.1962, "I_to conductance (Colman trace 0.1962; Ni 0.75471*0.1962)")             \
  X(k_to, "1", 1.0, "lineage factor on I_to (Ni 2017 drug code 1.05)")                                        \
  X(g_to_scale, "1", 1.0, "regional/AF scale of g_to")                                                        \
  X(Ito_r_shift_mV, "mV", 0.0, "I_to activation shift (Ni AF: +16 mV)")                                       \
  X(ito_tau_squared, "switch", 0.0,                                                                           \
    "1: Maleckar tau with exp(-x^2); 0: the code's exp(-2x) (quirk G1)")                                      \
  /* I_Kur */                                                                                                 \
  X(ikur_formulation, "switch", 0.0, "0: Maleckar 2009 r/s gates (Colman 2013); 1: Ni 2017 a/i")              \
  X(g_Kur_Maleckar_nS_per_pF, "nS/pF", 0.05874, "I_Kur conductance, Maleckar form")                           \
  X(g_Kur_Ni_nS_per_pF, "nS/pF", 0.006398 * 0.9, "I_Kur conductance, Ni 2017 form")                           \
  X(IKur_KQ10, "1", 3.0, "temperature factor dividing the Ni 2017 I_Kur time constants")                      \
  X(g_Kur_scale, "1", 1.0, "regional/AF scale of g_Kur")                                                      \
  X(IKur_act_shift_mV, "mV", 0.0, "I_Kur activation shift, applied as V + shift")                             \
  X(IKur_inact_shift_mV, "mV", 0.0, "I_Kur inactivation shift, applied as V + shift")                         \
  X(IKur_act_slope_scale, "1", 1.0, "scale of the I_Kur activation slope factor")                             \
  X(IKur_inact_slope_scale, "1", 1.0, "scale of the I_Kur inactivation slope factor")                         \
  /* I_Kr, I_Ks (CRN x0.8) */                                                                                 \
  X(g_Kr_nS_per_pF, "nS/pF", 0.029411765, "I_Kr conductance (CRN; Ni 2017 x0.8)")                             \
  X(g_Kr_scale, "1", 1.0, "regional/AF scale of g_Kr")                                                        \
  X(g_Ks_nS_per_pF, "nS/pF", 0.12941176, "I_Ks conductance (CRN; Ni 2017 x0.8)")                              \
  X(g_Ks_scale, "1", 1.0, "regional/AF scale of g_Ks")                                                        \
  X(IKs_shift_mV, "mV", 0.0, "I_Ks activation shift (steady state), V - 19.9 - shift")                        \
  X(IKs_slope_scale, "1", 1.0, "scale of the I_Ks activation slope factor")                                   \
  /* I_CaL (CRN, f_Ca on Ca_ss) */                                                                            \
  X(g_CaL_nS_per_pF, "nS/pF", 0.1294, "I_CaL conductance before k_CaL (Ni 2017 0.1294*0.75)")                 \
  X(k_CaL, "1", 2.125, "lineage factor on I_CaL (Colman 2.125, Ni 2017 1.333333)")                            \
  X(g_CaL_scale, "1", 1.0, "regional/AF scale of g_CaL")                                                      \
  X(E_CaL_mV, "mV", 65.0, "I_CaL reversal potential")                                                         \
  X(ICaL_f_tau_scale, "1", 0.865, "scale of the f-gate time constant (colman2013 fit 0.865; Ni 1; AF x1.62)") \
  /* I_K1 */                                                                                                  \
  X(g_K1_nS_per_pF, "nS/pF", 0.09, "I_K1 conductance (CRN)")                                                  \
  X(g_K1_scale, "1", 1.0, "regional/AF scale of g_K1")                                                        \
  /* background currents */                                                                                   \
  X(g_bNa_nS_per_pF, "nS/pF", 0.0006744375, "I_bNa conductance (CRN)")                                        \
  X(k_bNa, "1", 1.0, "lineage factor on I_bNa (Ni 2017 0.8*1.7)")                                             \
  X(g_bCa_nS_per_pF, "nS/pF", 0.001131, "I_bCa conductance (CRN)")                                            \
  X(k_bCa, "1", 1.0, "lineage factor on I_bCa (Ni 2017 1.4)")                                                 \
  X(g_ab_nS_per_pF, "nS/pF", 0.0003879, "I_ab scale, Zhang-lab background current")                           \
  X(k_ab, "1", 1.0, "factor on I_ab (Colman 1; Ni 2017 0)")                                                   \
  /* stretch-activated non-selective cation current, as active at rest (seed paper 2.1.1; Zhang 2000) */       \
  X(g_SAC_nS_per_pF, "nS/pF", 0.0, "I_SAC conductance at the cell's resting stretch (0: off)")                 \
  X(E_SAC_mV, "mV", -6.1, "I_SAC reversal potential (Zhang et al. 2000, rat atrial myocytes)")                \
  /* pumps and exchanger (CRN, on Ca_ss) */                                                                   \
  X(ICap_max_pA_per_pF, "pA/pF", 0.275, "sarcolemmal Ca pump maximum (CRN)")                                  \
  X(Km_Cap_mM, "mM", 0.0005, "sarcolemmal Ca pump half saturation (CRN)")                                     \
  X(k_Cap, "1", 1.26, "lineage factor on I_CaP (1.26 in both codes)")                                         \
  X(k_NaCa_pA_per_pF, "pA/pF", 1600.0, "I_NaCa scale (CRN)")                                                  \
  X(Km_Na_NaCa_mM, "mM", 87.5, "I_NaCa Na half saturation (CRN)")                                             \
  X(Km_Ca_NaCa_mM, "mM", 1.38, "I_NaCa Ca half saturation (CRN)")                                             \
  X(k_sat_NaCa, "1", 0.1, "I_NaCa saturation factor (CRN)")                                                   \
  X(gamma_NaCa, "1", 0.35, "I_NaCa voltage dependence (CRN)")                                                 \
  X(k_NaCa, "1", 1.0, "lineage factor on I_NaCa (Ni 2017 1.4)")                                               \
  X(g_NaCa_scale, "1", 1.0, "regional/AF scale of I_NaCa")                                                    \
  X(INaK_max_pA_per_pF, "pA/pF", 0.59933874, "I_NaK maximum (CRN)")                                           \
  X(k_NaK, "1", 1.0, "lineage factor on I_NaK (Ni 2017 1.4*1.28)")                                            \
  X(Km_K_NaK_mM, "mM", 1.5, "I_NaK K_o half saturation (CRN)")                                                \
  X(Km_Na_NaK_mM, "mM", 10.0, "I_NaK Na_i half saturation (CRN)")                                             \
  X(hill_Na_NaK, "1", 1.5, "I_NaK Na_i Hill coefficient (CRN 1.5, Ni 2017 4)")                                \
  /* concentrations */                                                                                        \
  X(Na_i_clamped, "switch", 1.0, "1: dNa_i/dt = 0 (Colman 2013 trace); 0: dynamic Na_i")                      \
  /* Ca handling (simplified Koivumaki 2011) */                                                               \
  X(D_Ca_um2_per_ms, "um^2/ms", 0.78, "cytosolic Ca diffusion coefficient")                                   \
  X(k_j_nj, "1", 1.0, "factor on junctional->bulk diffusion (Ni 2017 2.5)")                                   \
  X(D_CaSR_um2_per_ms, "um^2/ms", 0.044, "SR Ca diffusion coefficient")                                       \
  X(SR_rate_factor, "1", 1000.0, "factor on dCa_SR/dt (both codes 1000, quirk G2; physical 1)")               \
  X(k_SR_leak_per_ms, "1/ms", 6e-6, "SR leak rate")                                                           \
  X(k_leak, "1", 1.0, "lineage factor on SR leak (Ni 2017 0.5)")                                              \
  X(SR_leak_scale, "1", 1.0, "regional/AF scale of SR leak (Ni AF 1.5)")                                      \
  X(SERCA_k1_per_ms_mM2, "1/ms/mM^2", 7500.0, "SERCA cytosolic binding rate")                                 \
  X(SERCA_k2_per_ms, "1/ms", 4.6875e-4, "SERCA cytosolic unbinding rate")                                     \
  X(SERCA_k3_per_ms_mM2, "1/ms/mM^2", 2.314815e-3, "SERCA SR-side binding rate")                              \
  X(SERCA_k4_per_ms, "1/ms", 7.5e-3, "SERCA pump rate")                                                       \
  X(SERCA_pumps_mM, "mM", 40e-3, "SERCA pump concentration")                                                  \
  X(k_SERCA, "1", 1.0, "lineage factor on all SERCA fluxes (Ni 2017 0.75)")                                   \
  X(SERCA_scale, "1", 1.0, "regional/AF scale of SERCA (Ni AF 0.6)")                                          \
  X(SERCA_bulk_const, "1", 1.063, "BULK_CONST on cytosolic SERCA uptake (colman2013 fit 1.063; Ni 1)")        \
  X(SERCA_state_factor, "1", 0.5, "factor on dSERCACa/dt, dSERCACass/dt (Colman 0.5; Ni 1)")                  \
  X(RyR_nu_i_per_ms, "1/ms", 1e-3, "bulk RyR release rate")                                                   \
  X(RyR_nu_ss_per_ms, "1/ms", 0.625, "junctional RyR release rate")                                           \
  X(RyR_Ca_sens_i_per_mM, "1/mM", 1000.0, "bulk RyR Ca sensitivity (mM->uM; Ni 2017 2000)")                   \
  X(RyR_Ca_sens_ss_per_mM, "1/mM", 1000.0, "junctional RyR Ca sensitivity (mM->uM)")                          \
  X(fRyR, "1", 0.0, "extra RyR Ca sensitivity (Ni AF 2.5)")                                                   \
  X(tau_RyR_o_i_ms, "ms", 18.75, "bulk RyR activation time constant (Ni 2017 5)")                             \
  X(tau_RyR_c_i_ms, "ms", 87.5, "bulk RyR inactivation time constant (Ni 2017 30)")                           \
  X(tau_RyR_a_i_ms, "ms", 1000.0, "bulk RyR adaptation time constant (Ni 2017 250)")                          \
  X(tau_RyR_o_ss_ms, "ms", 5.0, "junctional RyR activation time constant")                                    \
  X(tau_RyR_c_ss_ms, "ms", 15.0, "junctional RyR inactivation time constant")                                 \
  X(tau_RyR_a_ss_ms, "ms", 1000.0, "junctional RyR adaptation time constant (Ni 2017 250)")                   \
  X(RyR_tau_scale, "1", 1.0, "scale of RyR c and a time constants (Ni AF 2.7)")                               \
  X(g_rel_scale, "1", 1.0, "regional/AF scale of RyR release (Ni AF 3)")                                      \
  X(B_Ca_mM, "mM", 24e-3, "cytosolic Ca buffer")                                                              \
  X(Kd_BCa_mM, "mM", 2.38e-3, "cytosolic Ca buffer Kd")                                                       \
  X(SL_low_mM, "mM", 165.0, "sarcolemmal low-affinity buffer")                                                \
  X(Kd_SLlow_mM, "mM", 1.1, "its Kd")                                                                         \
  X(SL_high_mM, "mM", 13.0, "sarcolemmal high-affinity buffer")                                               \
  X(Kd_SLhigh_mM, "mM", 13e-3, "its Kd")                                                                      \
  X(CSQN_mM, "mM", 6.7, "calsequestrin")                                                                      \
  X(Kd_CSQN_mM, "mM", 0.8, "calsequestrin Kd")

#define COLMAN_ENUM(name, ...) k_##name,
enum State { COLMAN_STATES(COLMAN_ENUM) kNumStates };
enum Param { COLMAN_PARAMS(COLMAN_ENUM) kNumParams };
#undef COLMAN_ENUM

enum Input { kI_ext, kJ_TRPN };
enum Output {
  kOut_I_ion,
  kOut_Ca_i,
  kOut_Ca_ss,
  kOut_INa,
  kOut_Ito,
  kOut_IKur,
  kOut_IKr,
  kOut_IKs,
  kOut_ICaL,
  kOut_IK1,
  kOut_INaCa,
  kOut_INaK,
  kOut_ISAC,
  kNumOutputs
};

FIBRODEM_USE_LANE_MATH;

// Per-call view of the parameters, so the equations read like the paper.
struct Par {
  const double* p;
  double operator[](int k) const { return p[k]; }
};

// Gate rates are generic in R: lanes of cells (simd::Real) or one cell (double).
template <class R>
struct Gate {
  R inf;
  R tau;
};
template <class R>
struct AlphaBeta {
  R alpha;
  R beta;
};

// ---- I_Na (CRN 1998 eqs. as in ni-2017.mmt [ina]) -------------------------
template <class R>
AlphaBeta<R> ina_m(const R& V, double shift) {
  const R x = V - shift + 47.13;
  // 0.32 x / (1 - exp(-0.1 x)) = 3.2 * exprel(0.1 x); limit 3.2 /ms at x = 0
  return {3.2 * exprel(R(0.1 * x)), 0.08 * exp(-(V - shift) / 11.0)};
}
// h and j switch form at V = -40 mV (both forms are evaluated, one kept).
template <class R>
AlphaBeta<R> ina_h(const R& V) {
  const auto above = V >= -40.0;
  return {select(above, 0.0, 0.135 * exp((V + 80.0) / -6.8)),
          select(above, 1.0 / (0.13 * (1.0 + exp((V + 10.66) / -11.1))),
                 3.56 * exp(0.079 * V) + 3.1e5 * exp(0.35 * V))};
}
template <class R>
AlphaBeta<R> ina_j(const R& V) {
  const auto above = V >= -40.0;
  return {select(above, 0.0,
                 (-1.2714e5 * exp(0.2444 * V) - 3.474e-5 * exp(-0.04391 * V)) * (V + 37.78) /
                     (1.0 + exp(0.311 * (V + 79.23)))),
          select(above, 0.3 * exp(-2.535e-7 * V) / (1.0 + exp(-0.1 * (V + 32.0))),
                 0.1212 * exp(-0.01052 * V) / (1.0 + exp(-0.1378 * (V + 40.14))))};
}

// ---- I_Kr, I_Ks (CRN) -----------------------------------------------------
template <class R>
Gate<R> ikr_xr(const R& V) {
  // a = 0.0003 (V+14.1)/(1 - exp((V+14.1)/-5))        -> 0.0015 exprel((V+14.1)/5)
  // b = 7.3898e-5 (V-3.3328)/(exp((V-3.3328)/5.1237)-1) -> 7.3898e-5*5.1237 exprel(-(V-3.3328)/5.1237)
  const R a = 0.0015 * exprel(R((V + 14.1) / 5.0));
  const R b = 0.000073898 * 5.1237 * exprel(R(-(V - 3.3328) / 5.1237));
  return {1.0 / (1.0 + exp((V + 14.1) / -6.5)), 1.0 / (a + b)};
}
template <class R>
Gate<R> iks_xs(const R& V, double shift, double slope_scale) {
  // a = 4e-5 (V-19.9)/(1 - exp((V-19.9)/-17)) -> 0.00068 exprel((V-19.9)/17)
  // b = 3.5e-5 (V-19.9)/(exp((V-19.9)/9) - 1) -> 0.000315 exprel(-(V-19.9)/9)
  const R a = 0.00068 * exprel(R((V - 19.9) / 17.0));
  const R b = 0.000315 * exprel(R(-(V - 19.9) / 9.0));
  return {sqrt(1.0 / (1.0 + exp((V - 19.9 - shift) / (-12.7 * slope_scale)))), 0.5 / (a + b)};
}

// ---- I_CaL (CRN; f_Ca on Ca_ss) -------------------------------------------
template <class R>
Gate<R> ical_d(const R& V) {
  // tau = a (1 - exp(-(V+10)/6.24)) / (0.035 (V+10)) = a / (0.035*6.24 exprel((V+10)/6.24));
  // limit a * 4.5788 ms at V = -10 (the code uses 4.579).
  const R a = 1.0 / (1.0 + exp((V + 10.0) / -6.24));
  return {1.0 / (1.0 + exp((V + 10.0) / -8.0)), a / (0.035 * 6.24 * exprel(R((V + 10.0) / 6.24)))};
}
template <class R>
Gate<R> ical_f(const R& V, double tau_scale) {
  const R e = exp(-(V + 28.0) / 6.9);
  const R tau = 1.5 * 2.0 * 3.0 / (0.0197 * exp(-(0.0337 * 0.0337) * (V + 10.0) * (V + 10.0)) + 0.02);
  return {e / (1.0 + e), tau * tau_scale};
}

// ---- I_to (Maleckar 2009 r/s) ---------------------------------------------
// The code writes exp(-(V/30)*2) where Maleckar has exp(-(V/30)^2) (quirk G1).
template <class R>
R ito_shape(const R& x, bool squared) {
  return squared ? R(x * x) : R(2.0 * x);
}
template <class R>
Gate<R> ito_r(const R& V, double shift, bool squared) {
  return {1.0 / (1.0 + exp((V - shift - 1.0) / -11.0)),
          3.5 * exp(-ito_shape(R((V - shift) / 30.0), squared)) + 1.5};
}
template <class R>
Gate<R> ito_s(const R& V, bool squared) {
  return {1.0 / (1.0 + exp((V + 40.5) / 11.5)),
          25.635 * exp(-ito_shape(R((V + 52.45) / 15.8827), squared)) + 14.14};
}

// ---- I_Kur ----------------------------------------------------------------
// Maleckar 2009 (Colman 2013; A1 IKur_type_CNZ == 0), taus given in s there.
template <class R>
Gate<R> ikur_r_maleckar(const R& V, double shift, double slope) {
  return {1.0 / (1.0 + exp(-(V + shift + 6.0) / (8.6 * slope))), 9.0 / (1.0 + exp((V + 5.0) / 12.0)) + 0.5};
}
template <class R>
Gate<R> ikur_s_maleckar(const R& V, double shift, double slope) {
  return {1.0 / (1.0 + exp((V + shift + 7.5) / (10.0 * slope))), 590.0 / (1.0 + exp((V + 60.0) / 10.0)) + 3050.0};
}
// Ni 2017 (ni-2017.mmt [ikur]).
template <class R>
Gate<R> ikur_a_ni(const R& V, double shift, double slope, double KQ10) {
  const R tau = (45.6666746826 / (1.0 + exp((V + 11.2306497073) / 11.5254705962)) + 4.26753514993) *
                (0.262186042981 / (1.0 + exp((V + 35.8658312707) / -3.87510627762)) + 0.291755017928);
  return {1.0 / (1.0 + exp(-(V + shift + 5.52) / (8.6 * slope))), tau / KQ10};
}
template <class R>
Gate<R> ikur_i_ni(const R& V, double shift, double slope, double KQ10) {
  return {0.52424 / (1.0 + exp((V + shift + 15.1142) / (7.567021 * slope))) + 0.4580778,
          (2328.0 / (1.0 + exp((V - 9.435) / 3.5827)) + 1739.139) / KQ10};
}

// ---- RyR gates (Koivumaki 2011), Ca in mM times sensitivity (1/mM -> uM) ---
template <class R>
struct RyRGates {
  Gate<R> o, c, a;
};
template <class R>
RyRGates<R> ryr_gates(const R& ca_uM, const R& a_state, double tau_o, double tau_c, double tau_a) {
  return {{1.0 - 1.0 / (1.0 + exp((ca_uM - (a_state + 0.22)) / 0.03)), R(tau_o)},
          {1.0 / (1.0 + exp((ca_uM - (a_state + 0.02)) / 0.01)), R(tau_c)},
          {0.505 - 0.427 / (1.0 + exp((ca_uM - 0.29) / 0.082)), R(tau_a)}};
}

class Colman final : public fibrodem::CellModel {
 public:
  Colman();
  const fibrodem::ModelInfo& info() const override { return info_; }
  void evaluate(const fibrodem::BlockView& block, double t_ms) const override;

 private:
  fibrodem::ModelInfo info_;
};

void Colman::evaluate(const fibrodem::BlockView& block, double /*t_ms*/) const {
  const Par P{block.params};
  const double Cm = P[k_Cm_pF];
  const double F = P[k_F_C_per_mmol];
  const double FRT = F / (P[k_R_J_per_mol_K] * P[k_T_K]);
  const double Nao = P[k_Na_o_mM], Cao = P[k_Ca_o_mM], Ko = P[k_K_o_mM];
  const double Vi = P[k_Vi_um3], Vss = P[k_Vss_um3], Vnj = P[k_Vnj_um3];
  const double VSRi = P[k_VSRi_um3], VSRss = P[k_VSRss_um3];
  const double dx2 = P[k_dx_um] * P[k_dx_um];
  const bool ito_sq = P[k_ito_tau_squared] > 0.5;
  const bool ikur_ni = P[k_ikur_formulation] > 0.5;
  const bool nai_clamped = P[k_Na_i_clamped] > 0.5;
  // Gates marked voltage_only (rates from V and the parameters alone) may be
  // left to the core's lookup table.
  const bool skip_v = block.skip_voltage_only_gates;

  // Voltage-independent factors of the pumps/exchanger (CRN).
  const double sigma = (std::exp(Nao / 67.3) - 1.0) / 7.0;
  const double naca_scale = P[k_k_NaCa] * P[k_g_NaCa_scale] * Cm * P[k_k_NaCa_pA_per_pF] /
                            (std::pow(P[k_Km_Na_NaCa_mM], 3) + Nao * Nao * Nao) /
                            (P[k_Km_Ca_NaCa_mM] + Cao);
  const double gam = P[k_gamma_NaCa];
  const double nak_scale = P[k_k_NaK] * Cm * P[k_INaK_max_pA_per_pF] * Ko / (Ko + P[k_Km_K_NaK_mM]);

  fibrodem::for_each_lane_group(block, [&](const auto& cell) {
    using R = typename std::decay_t<decltype(cell)>::Real;
    const R V = cell.state(k_V);
    const R Nai = cell.state(k_Na_i), Ki = cell.state(k_K_i);
    const R Cai = cell.state(k_Ca_i), Cass = cell.state(k_Ca_ss);
    const R CaSRi = cell.state(k_Ca_SRi), CaSRss = cell.state(k_Ca_SRss);
    const R SERCACa = cell.state(k_SERCACa), SERCACass = cell.state(k_SERCACass);

    // Reversal potentials ([nernst]; E_Ca on bulk Ca_i).
    const R ENa = P[k_nernst_mono_mV] * log(Nao / Nai);
    const R EK = P[k_nernst_mono_mV] * log(Ko / Ki);
    const R ECa = P[k_nernst_Ca_mV] * log(Cao / Cai);

    // I_Na
    const R m = cell.state(k_m), h = cell.state(k_h), j = cell.state(k_j);
    const R INa = Cm * P[k_g_Na_nS_per_pF] * P[k_g_Na_scale] * m * m * m * h * j * (V - ENa);
    if (!skip_v) {
      const auto am = ina_m(V, P[k_INa_m_shift_mV]);
      const auto ah = ina_h(V);
      const auto aj = ina_j(V);
      cell.gate_alpha_beta(k_m, am.alpha, am.beta);
      cell.gate_alpha_beta(k_h, ah.alpha, ah.beta);
      cell.gate_alpha_beta(k_j, aj.alpha, aj.beta);
    }

    // I_to
    const R Ito = P[k_k_to] * Cm * P[k_g_to_nS_per_pF] * P[k_g_to_scale] * cell.state(k_ito_r) *
                       cell.state(k_ito_s) * (V - EK);
    if (!skip_v) {
      const auto gr = ito_r(V, P[k_Ito_r_shift_mV], ito_sq);
      const auto gs = ito_s(V, ito_sq);
      cell.gate_inf_tau(k_ito_r, gr.inf, gr.tau);
      cell.gate_inf_tau(k_ito_s, gs.inf, gs.tau);
    }

    // I_Kur: the two formulations share the states ikur_a (activation) and ikur_i (inactivation).
    const R ka = cell.state(k_ikur_a), ki = cell.state(k_ikur_i);
    R IKur;
    if (ikur_ni) {
      IKur = Cm * P[k_g_Kur_Ni_nS_per_pF] * P[k_g_Kur_scale] *
             (4.5128 + 1.899769 / (1.0 + exp((V - 20.5232) / -8.26597))) * ka * ki * (V - EK);
      if (!skip_v) {
        const auto ga = ikur_a_ni(V, P[k_IKur_act_shift_mV], P[k_IKur_act_slope_scale], P[k_IKur_KQ10]);
        const auto gi = ikur_i_ni(V, P[k_IKur_inact_shift_mV], P[k_IKur_inact_slope_scale], P[k_IKur_KQ10]);
        cell.gate_inf_tau(k_ikur_a, ga.inf, ga.tau);
        cell.gate_inf_tau(k_ikur_i, gi.inf, gi.tau);
      }
    } else {
      IKur = Cm * P[k_g_Kur_Maleckar_nS_per_pF] * P[k_g_Kur_scale] * ka * ki * (V - EK);
      if (!skip_v) {
        const auto ga = ikur_r_maleckar(V, P[k_IKur_act_shift_mV], P[k_IKur_act_slope_scale]);
        const auto gi = ikur_s_maleckar(V, P[k_IKur_inact_shift_mV], P[k_IKur_inact_slope_scale]);
        cell.gate_inf_tau(k_ikur_a, ga.inf, ga.tau);
        cell.gate_inf_tau(k_ikur_i, gi.inf, gi.tau);
      }
    }

    // I_Kr
    const R IKr = Cm * P[k_g_Kr_nS_per_pF] * P[k_g_Kr_scale] * cell.state(k_xr) * (V - EK) /
                       (1.0 + exp((V + 15.0) / 22.4));
    if (!skip_v) {
      const auto gxr = ikr_xr(V);
      cell.gate_inf_tau(k_xr, gxr.inf, gxr.tau);
    }

    // I_Ks
    const R xs = cell.state(k_xs);
    const R IKs = Cm * P[k_g_Ks_nS_per_pF] * P[k_g_Ks_scale] * xs * xs * (V - EK);
    if (!skip_v) {
      const auto gxs = iks_xs(V, P[k_IKs_shift_mV], P[k_IKs_slope_scale]);
      cell.gate_inf_tau(k_xs, gxs.inf, gxs.tau);
    }

    // I_CaL
    const R ICaL = P[k_k_CaL] * Cm * P[k_g_CaL_nS_per_pF] * P[k_g_CaL_scale] * cell.state(k_d) *
                        cell.state(k_f) * cell.state(k_fca) * (V - P[k_E_CaL_mV]);
    if (!skip_v) {
      const auto gd = ical_d(V);
      const auto gf = ical_f(V, P[k_ICaL_f_tau_scale]);
      cell.gate_inf_tau(k_d, gd.inf, gd.tau);
      cell.gate_inf_tau(k_f, gf.inf, gf.tau);
    }
    cell.gate_inf_tau(k_fca, 1.0 / (1.0 + Cass / 0.00035), 2.0);

    // I_K1
    const R IK1 =
        Cm * P[k_g_K1_nS_per_pF] * P[k_g_K1_scale] * (V - EK) / (1.0 + exp(0.07 * (V + 80.0)));

    // Background currents. I_ab: Cm*0.0003879*(V+69.6)/(1 - 0.8377 exp((V+49.06)/1056))
    // (A1 Updated_CNZ.cpp; it is the I_ab column of the original Colman trace).
    const R IbCa = P[k_k_bCa] * Cm * P[k_g_bCa_nS_per_pF] * (V - ECa);
    const R IbNa = P[k_k_bNa] * Cm * P[k_g_bNa_nS_per_pF] * (V - ENa);
    const R Iab = P[k_k_ab] * Cm * P[k_g_ab_nS_per_pF] * (V + 69.6) /
                       (1.0 - 0.8377 * exp((V + 49.06) / 1056.0));

    // I_CaP, I_NaCa (on Ca_ss), I_NaK
    const R ICap = P[k_k_Cap] * Cm * P[k_ICap_max_pA_per_pF] * Cass / (Cass + P[k_Km_Cap_mM]);
    const R INaCa = naca_scale / (1.0 + P[k_k_sat_NaCa] * exp((gam - 1.0) * V * FRT)) *
                         (Nai * Nai * Nai * Cao * exp(V * gam * FRT) -
                          Nao * Nao * Nao * Cass * exp(V * (gam - 1.0) * FRT));
    const R fnak = 1.0 / (1.0 + 0.1245 * exp(-0.1 * V * FRT) + 0.0365 * sigma * exp(-V * FRT));
    const R INaK = nak_scale * fnak / (1.0 + pow(P[k_Km_Na_NaK_mM] / Nai, P[k_hill_Na_NaK]));

    // I_SAC: the seed paper adds a stretch-activated current to I_m (2.1.1, after
    // Brocklehurst 2015, 2017); its formulation is not published in the text we
    // could read, so it is taken as the measured non-selective cation SAC of atrial
    // myocytes: linear I-V, reversal -6.1 mV (Zhang YH et al., J Physiol 523:607,
    // 2000), I_SAC = Cm g_SAC (V - E_SAC), its conductance held at the value of the
    // cell's resting stretch (examples/paper/NOTES.md). Carried by Na+ and K+ both,
    // it enters no concentration (Na_i, K_i clamped in colman2013). Added last, so
    // with g_SAC = 0 I_ion is bit-identical to the model without it.
    const R Isac = Cm * P[k_g_SAC_nS_per_pF] * (V - P[k_E_SAC_mV]);
    const R I_ion =
        INa + Ito + IKur + IKr + IKs + ICaL + IK1 + IbNa + IbCa + Iab + INaCa + INaK + ICap + Isac;
    cell.rate(k_V, (cell.input(kI_ext) - I_ion) / Cm);

    // Na_i (CRN, no stimulus term), K_i constant in both codes.
    cell.rate(k_Na_i, nai_clamped ? R(0.0) : R((-3.0 * INaK - 3.0 * INaCa - IbNa - INa) / (F * Vi)));
    cell.rate(k_K_i, 0.0);

    // ---- Ca handling ([ryr], [serca], [calcium]); fluxes in um^3*mM/ms ----
    // RyR gates
    const double ts = P[k_RyR_tau_scale];
    const R sens_i = P[k_RyR_Ca_sens_i_per_mM] * Cai * (1.0 + P[k_fRyR]);
    const R sens_ss = P[k_RyR_Ca_sens_ss_per_mM] * Cass * (1.0 + P[k_fRyR]);
    const R o_i = cell.state(k_ryr_o_i), c_i = cell.state(k_ryr_c_i);
    const R o_ss = cell.state(k_ryr_o_ss), c_ss = cell.state(k_ryr_c_ss);
    const auto gi = ryr_gates(sens_i, cell.state(k_ryr_a_i), P[k_tau_RyR_o_i_ms],
                                  P[k_tau_RyR_c_i_ms] * ts, P[k_tau_RyR_a_i_ms] * ts);
    const auto gss = ryr_gates(sens_ss, cell.state(k_ryr_a_ss), P[k_tau_RyR_o_ss_ms],
                                   P[k_tau_RyR_c_ss_ms] * ts, P[k_tau_RyR_a_ss_ms] * ts);
    cell.gate_inf_tau(k_ryr_o_i, gi.o.inf, gi.o.tau);
    cell.gate_inf_tau(k_ryr_c_i, gi.c.inf, gi.c.tau);
    cell.gate_inf_tau(k_ryr_a_i, gi.a.inf, gi.a.tau);
    cell.gate_inf_tau(k_ryr_o_ss, gss.o.inf, gss.o.tau);
    cell.gate_inf_tau(k_ryr_c_ss, gss.c.inf, gss.c.tau);
    cell.gate_inf_tau(k_ryr_a_ss, gss.a.inf, gss.a.tau);

    // Release
    const R RyRSRCai = 1.0 - 1.0 / (1.0 + exp((CaSRi - 0.3) / 0.1));
    const R RyRSRCass = 1.0 - 1.0 / (1.0 + exp((CaSRss - 0.3) / 0.1));
    const R Jreli =
        P[k_g_rel_scale] * P[k_RyR_nu_i_per_ms] * Vnj * o_i * c_i * RyRSRCai * (CaSRi - Cai);
    const R Jrelss =
        P[k_g_rel_scale] * P[k_RyR_nu_ss_per_ms] * Vss * o_ss * c_ss * RyRSRCass * (CaSRss - Cass);

    // SERCA (2-state pump); the "* 2" and the lineage factor are the code's.
    const double serca = P[k_k_SERCA] * P[k_SERCA_scale] * 2.0;
    const double k1 = P[k_SERCA_k1_per_ms_mM2], k2 = P[k_SERCA_k2_per_ms];
    const double k3 = P[k_SERCA_k3_per_ms_mM2], k4 = P[k_SERCA_k4_per_ms];
    const double cp = P[k_SERCA_pumps_mM];
    const R J_SERCASR = serca * (-k3 * CaSRi * CaSRi * (cp - SERCACa) + k4 * SERCACa) * Vnj;
    const R J_SERCASRss = serca * (-k3 * CaSRss * CaSRss * (cp - SERCACass) + k4 * SERCACass) * Vss;
    const R J_bulkSERCA = serca * (k1 * Cai * Cai * (cp - SERCACa) - k2 * SERCACa) * Vnj;
    const R J_bulkSERCAss = serca * (k1 * Cass * Cass * (cp - SERCACass) - k2 * SERCACass) * Vss;
    cell.rate(k_SERCACa, P[k_SERCA_state_factor] * (-J_SERCASR + J_bulkSERCA) / Vnj);
    cell.rate(k_SERCACass, P[k_SERCA_state_factor] * (-J_SERCASRss + J_bulkSERCAss) / Vss);

    // Diffusion junctional -> bulk, SR leak
    const R Jj_nj = P[k_k_j_nj] * P[k_D_Ca_um2_per_ms] * P[k_Aj_nj_um2] / P[k_xj_nj_um] * (Cass - Cai);
    const double leak = P[k_k_leak] * P[k_SR_leak_scale] * P[k_k_SR_leak_per_ms];
    const R JSRCaleaki = leak * (CaSRi - Cai) * Vnj;
    const R JSRCaleakss = leak * (CaSRss - Cass) * Vss;

    const double bulk = P[k_SERCA_bulk_const];
    const R JCa = -bulk * J_bulkSERCA + JSRCaleaki + Jreli + Jj_nj;
    const R JCass = -Jj_nj + JSRCaleakss - bulk * J_bulkSERCAss + Jrelss;
    const R JSRCai = J_SERCASR - JSRCaleaki - Jreli;
    const R JSRCass = J_SERCASRss - JSRCaleakss - Jrelss;

    // Bulk cytosol
    const double BCa = P[k_B_Ca_mM], KdBCa = P[k_Kd_BCa_mM];
    const R beta_i = 1.0 / (1.0 + BCa * KdBCa / ((Cai + KdBCa) * (Cai + KdBCa)));
    // J_TRPN: Ca binding to a myofilament model's troponin (fibrodem's
    // calcium_feedback; 0 otherwise). Colman has no troponin of its own: BCa
    // lumps the cytosolic buffers (Koivumaki 2011), so nothing is switched off.
    cell.rate(k_Ca_i, (JCa / Vnj - cell.input(kJ_TRPN)) * beta_i);

    // SR: the diffusion terms are the code's, verbatim (the bulk term simplifies).
    const double DCaSR = P[k_D_CaSR_um2_per_ms];
    const double CSQN = P[k_CSQN_mM], KdCSQN = P[k_Kd_CSQN_mM];
    const R beta_SRi = 1.0 / (1.0 + CSQN * KdCSQN / ((CaSRi + KdCSQN) * (CaSRi + KdCSQN)));
    const R beta_SRss = 1.0 / (1.0 + CSQN * KdCSQN / ((CaSRss + KdCSQN) * (CaSRss + KdCSQN)));
    // The SR compartments are the model's stiffest non-gate states (at rest
    // d(dCa_SRi/dt)/dCa_SRi ~ -20/ms: SERCA's SR-side binding and SR
    // diffusion, scaled by the x1000 rate factor), so each gives its slope:
    // SERCA, diffusion, leak and release in their own concentration (the
    // release's sigmoid and the buffer factor's own slopes left out; the slope
    // only steadies an exponential integrator, the rate is exact).
    const R dJSERCASR_dCaSRi = serca * (-2.0 * k3 * CaSRi * (cp - SERCACa)) * Vnj;
    const R dJSERCASRss_dCaSRss = serca * (-2.0 * k3 * CaSRss * (cp - SERCACass)) * Vss;
    const R dJreli_dCaSRi = P[k_g_rel_scale] * P[k_RyR_nu_i_per_ms] * Vnj * o_i * c_i * RyRSRCai;
    const R dJrelss_dCaSRss = P[k_g_rel_scale] * P[k_RyR_nu_ss_per_ms] * Vss * o_ss * c_ss * RyRSRCass;
    cell.stiff_rate(k_Ca_SRi,
                    P[k_SR_rate_factor] * beta_SRi *
                        (DCaSR * ((CaSRss - 2.0 * CaSRi + CaSRi) / dx2 + (CaSRi - CaSRss) / (2.0 * 3.0 * dx2)) +
                         JSRCai / VSRi),
                    P[k_SR_rate_factor] * beta_SRi *
                        (DCaSR * (-1.0 + 1.0 / 6.0) / dx2 +
                         (dJSERCASR_dCaSRi - leak * Vnj - dJreli_dCaSRi) / VSRi));
    cell.stiff_rate(k_Ca_SRss,
                    P[k_SR_rate_factor] * beta_SRss *
                        (DCaSR * ((CaSRss - 2.0 * CaSRss + CaSRi) / dx2 + (CaSRss - CaSRi) / (2.0 * 4.0 * dx2)) +
                         JSRCass / VSRss),
                    P[k_SR_rate_factor] * beta_SRss *
                        (DCaSR * (-1.0 + 1.0 / 8.0) / dx2 +
                         (dJSERCASRss_dCaSRss - leak * Vss - dJrelss_dCaSRss) / VSRss));

    // Junctional subspace (sarcolemmal currents in pA: pA/(um^3 C/mmol) = mM/ms)
    const double SLlow = P[k_SL_low_mM], KdSLlow = P[k_Kd_SLlow_mM];
    const double SLhigh = P[k_SL_high_mM], KdSLhigh = P[k_Kd_SLhigh_mM];
    const R beta_ss = 1.0 / (1.0 + SLlow * KdSLlow / ((Cass + KdSLlow) * (Cass + KdSLlow)) +
                                  SLhigh * KdSLhigh / ((Cass + KdSLhigh) * (Cass + KdSLhigh)) +
                                  BCa * KdBCa / ((Cass + KdBCa) * (Cass + KdBCa)));
    const R I_tot = -ICaL - IbCa - ICap + 2.0 * INaCa;
    cell.rate(k_Ca_ss, beta_ss * (JCass / Vss + I_tot / (2.0 * Vss * F)));

    cell.output(kOut_I_ion, I_ion);
    cell.output(kOut_Ca_i, Cai);
    cell.output(kOut_Ca_ss, Cass);
    cell.output(kOut_INa, INa);
    cell.output(kOut_Ito, Ito);
    cell.output(kOut_IKur, IKur);
    cell.output(kOut_IKr, IKr);
    cell.output(kOut_IKs, IKs);
    cell.output(kOut_ICaL, ICaL);
    cell.output(kOut_IK1, IK1);
    cell.output(kOut_INaCa, INaCa);
    cell.output(kOut_INaK, INaK);
    cell.output(kOut_ISAC, Isac);
  });
}

// ---------------------------------------------------------------------------
// Variants. Parameter defaults above are the colman2013 values; the ni2017 set
// below lists every parameter that differs (values of ni-2017.mmt, RA, no AF).
//
// colman2013. No code of the 2013 model is public. Its target is the authors'
// committed trace Original_Colman_Model.dat (HaiboNi/updated_cnz_for_ina_ikur_block_study,
// 2 beats at 1 Hz after 48 paced beats; columns t, V, 3 cytosolic Ca, Na_i, then
// currents in pA/pF). Replaying our gate equations under its V(t) identified:
//   I_to   Maleckar r/s with the exp(-2x) time constants of quirk G1 (its I_to stays
//          elevated through diastole exactly as the slow G1 r gate does; squared taus
//          would decay within ms) and g 0.1962 nS/pF (ratio to 0.75471*0.1962 = 1.325
//          at every sample);
//   I_Kur  Maleckar r/s, g 0.05874 nS/pF (ratio 1.000);
//   I_Kr, I_Ks CRN conductances, without the x0.8 (ratio 1.25);
//   I_CaL  2.125 * 0.1294 nS/pF (from the current balance: ratio ~2.83 to 0.1294*0.75);
//   I_NaCa CRN x1 on the sub-membrane Ca; I_NaK CRN (0.59933874, Km 10, Hill 1.5);
//   I_bNa, I_bCa CRN x1; I_CaP x1.26 (diastolic current balance); I_ab present;
//   Na_i 11.17 mM constant; K_i 114.76 mM (from E_K of its I_K1 column).
// The Ca system follows the A1 "original" comments: Koivumaki RyR time constants (act
// 18.75, inact 87.5, adapt 1000 ms; junctional 5, 15), bulk RyR sensitivity x1 (not
// x2), SR leak x1, junctional diffusion x1, SERCA x1, 0.5 on the SERCA state equations;
// and quirk G2 (SR factor 1000), without which the Ca transient peaks at ~65 ms
// instead of ~100 ms. Two constants were then fitted (Nelder-Mead, RMS of V and of the
// two Ca traces over the beat): SERCA_bulk_const 1.063 (A1's RA BULK_CONST is 1.25; with
// 1.25 Ca_i is 0.145 -> 0.49 uM) and ICaL_f_tau_scale 0.865. Result at 1 Hz (dt 0.02
// ms): RMS(V - V_ref) 0.28 mV, Ca_i within 2 nM of the reference's bulk column and
// Ca_ss within 3 nM of its sub-membrane column. Initial state: beat 300 of this
// variant from A1's commented rest state. The "Colman lineage" factors
// (docs/reference/references.md#colman-2013) of x0.8 for I_Kr/I_Ks,
// x0.8/x1.4 for the background currents and x1.4, Km 9.5 for I_NaK are the A1
// header's values, which the trace does not show.
struct Override {
  const char* name;
  double ni2017;
};
const Override kNi2017Params[] = {
    {"g_to_nS_per_pF", 0.75471 * 0.1962},  // gto
    {"k_to", 1.05},                     // Ito = 1.05 * fto * Cm * gto * r * s * (V - EK)
    {"ito_tau_squared", 0.0},           // G1 kept: exp(-(x)*2)
    {"ikur_formulation", 1.0},          // CNZ a/i gates, g 0.006398*0.9
    {"g_CaL_nS_per_pF", 0.1294 * 0.75}, // gCaL
    {"k_CaL", 1.333333},                // ICaL = 1.333333 * Cm * gCaL * d f fca (V - ErL)
    {"ICaL_f_tau_scale", 1.0},          // f tau = 1.5*2*3/(...)
    {"g_Kr_nS_per_pF", 0.8 * 0.029411765},  // gKr
    {"g_Ks_nS_per_pF", 0.8 * 0.12941176},   // gKs
    {"k_bNa", 0.8 * 1.7},               // gbNa = 0.8*0.0006744375; IbNa = 1.7 * ...
    {"k_bCa", 1.4},                     // gbCa = 1.4*0.001131; IbCa = 1.0 * ...
    {"k_ab", 0.0},                      // no I_ab in ni-2017.mmt
    {"k_NaCa", 1.4},                    // INaCa = 1.4 * scaling * ...
    {"k_NaK", 1.4 * 1.28},              // I_bar = 1.4*0.59933874; INaK = 1.28 * ...
    {"Km_Na_NaK_mM", 10.0},             // kmnai
    {"hill_Na_NaK", 4.0},               // (kmnai/Na_i)^4
    {"Na_i_clamped", 0.0},              // dot(Na_i) dynamic
    {"k_j_nj", 2.5},                    // Jj_nj = 2.5 * DCa * ...
    {"k_leak", 0.5},                    // JSRCaleak = 0.5 * ...
    {"k_SERCA", 0.75},                  // J_SERCA = 0.75 * ...
    {"SERCA_bulk_const", 1.0},          // no BULK_CONST
    {"SERCA_state_factor", 1.0},        // dot(SERCACa) = (-J_SERCASR + J_bulkSERCA)/Vnj
    {"RyR_Ca_sens_i_per_mM", 2000.0},   // 2000 * Ca_i
    {"tau_RyR_o_i_ms", 5.0},            //
    {"tau_RyR_c_i_ms", 2.0 * 15.0},     //
    {"tau_RyR_a_i_ms", 250.0},          //
    {"tau_RyR_a_ss_ms", 250.0},         //
};

// ni-2017.mmt initial values (RA, 1 Hz).
const std::pair<const char*, double> kNi2017Initial[] = {
    {"V", -77.13255836},        {"m", 0.005631819916},     {"h", 0.9168420281},
    {"j", 0.9380183564},        {"d", 0.0002267161277},    {"f", 0.9354212881},
    {"xr", 0.00157418133},      {"xs", 0.02225979641},     {"Na_i", 10.30397012},
    {"Ca_i", 0.0001403133065},  {"K_i", 131.867138},       {"fca", 0.7270823666},
    {"ito_r", 0.01223706011},   {"ito_s", 0.8849139842},   {"Ca_ss", 0.0001313595105},
    {"Ca_SRi", 0.9892411621},   {"Ca_SRss", 0.9779168037}, {"SERCACa", 0.00958584702},
    {"SERCACass", 0.009386941118}, {"ryr_o_ss", 0.000456694441}, {"ryr_c_ss", 0.9571976502},
    {"ryr_a_ss", 0.1419271573}, {"ryr_o_i", 0.0003667999273}, {"ryr_c_i", 0.9790238698},
    {"ryr_a_i", 0.2977219443},  {"ikur_a", 0.0002417881801}, {"ikur_i", 0.9517278864},
};

// brocklehurst2022_tissue: colman2013 with the stretch-activated current I_SAC
// active at rest (seed paper 2.1.1; examples/paper/NOTES.md says why). One
// parameter, g_SAC, calibrated to one number: the seed paper's myocyte RMP of
// -65.2 mV (Fig. 4c) at F-M 0.11, D_f 0.3 nS, in-series (the fig3 in-series
// manifest on a 0.29 mm wide strip, seed 1, solver auto, RMP at the stimulus
// onset; bisection on g_SAC, scripts/calibrate_sac.py: -65.20 mV at 0.0036718).
const double kBrocklehurstGSac_nS_per_pF = 0.0036718;
// Its initial state: the variant's own rest, one uncoupled cell unpaced for 60 s
// from the colman2013 initial state (cells.myocyte.settle {"ms": 60000}; 20 s
// gives V within 0.008 mV of this).
const std::pair<const char*, double> kBrocklehurstInitial[] = {
    {"V", -65.44348378},  {"m", 0.03515381356},  {"h", 0.4391538582},
    {"j", 0.4398370892},  {"d", 0.0009766203513},  {"f", 0.9956211987},
    {"fca", 0.7104426241},  {"xr", 0.0003709777222},  {"xs", 0.03471502788},
    {"ito_r", 0.002375150017},  {"ito_s", 0.8974308246},  {"ikur_a", 0.0009947409251},
    {"ikur_i", 0.9969645273},  {"Na_i", 11.17},  {"K_i", 114.76},
    {"Ca_i", 0.0001340331997},  {"Ca_ss", 0.0001426506213},  {"Ca_SRi", 0.6296018422},
    {"Ca_SRss", 0.6198458632},  {"SERCACa", 0.004666077091},  {"SERCACass", 0.004625552782},
    {"ryr_o_ss", 0.000744072705},  {"ryr_c_ss", 0.8331171724},  {"ryr_a_ss", 0.1387294451},
    {"ryr_o_i", 0.0006655952797},  {"ryr_c_i", 0.8746253082},  {"ryr_a_i", 0.1334580883},
};

// colman2013_caf: chronic-AF electrical remodelling of Colman et al. 2013 (J Physiol
// 591:4249; the set that remodels Ca handling as well as the currents), on
// colman2013. The factors are those of the first author's own code of the paper's
// remodelling sets (michaelcolman/MSCSF, lib/Model.c set_remodelling_hAM(),
// "AF_Col_4", commented "Colman et al. 2013 J Physiol 591(17):4249-72"), applied as
// the model's AF scale parameters.
const std::pair<const char*, double> kColman2013CafScales[] = {
    {"g_CaL_scale", 0.30},   // GCaL x 0.3 (-70 %)
    {"g_to_scale", 0.34},    // Gto x 0.34 (-66 %)
    {"g_Kur_scale", 0.50},   // GKur x 0.5 (-50 %)
    {"g_K1_scale", 2.0},     // GK1 x 2 (+100 %)
    {"g_Ks_scale", 2.0},     // GKs x 2 (+100 %)
    {"g_NaCa_scale", 1.55},  // GNCX x 1.55 (+55 %)
    {"SR_leak_scale", 1.25}, // Gleak x 1.25 (+25 %)
    {"g_rel_scale", 3.0},    // Grel x 3 (RyR release, +200 %)
};
// Its initial state: its own 1 Hz steady state, the state before the 301st
// stimulus of 300 beats (2000 pA x 2 ms, Rush-Larsen, dt 0.02 ms) from
// colman2013's; APD90 then changes by < 0.01 ms a beat (120.94 ms at beat 300).
const std::pair<const char*, double> kColman2013CafInitial[] = {
    {"V", -78.41583885},  {"m", 0.004572721191},  {"h", 0.9364126617},  {"j", 0.9551968818},
    {"d", 0.0001931254604},  {"f", 0.9801752821},  {"fca", 0.7890654839},  {"xr", 0.0005451760756},
    {"xs", 0.02093176315},  {"ito_r", 0.01843573801},  {"ito_s", 0.8636999359},
    {"ikur_a", 0.0002202618245},  {"ikur_i", 0.9753171417},  {"Na_i", 11.17},  {"K_i", 114.76},
    {"Ca_i", 9.795236531e-05},  {"Ca_ss", 9.355923302e-05},  {"Ca_SRi", 0.4531212802},
    {"Ca_SRss", 0.4481489601},  {"SERCACa", 0.002648059743},  {"SERCACass", 0.002573796146},
    {"ryr_o_ss", 0.0001714719665},  {"ryr_c_ss", 0.9976027195},  {"ryr_a_ss", 0.1335951506},
    {"ryr_o_i", 0.000273046044},  {"ryr_c_i", 0.9903669221},  {"ryr_a_i", 0.1240645743},
};

Colman::Colman() {
  info_.name = "colman";
  info_.version = "1.0.0";
  info_.description =
      "Colman et al. 2013 human atrial myocyte (right atrium): CRN 1998 with Maleckar 2009 I_to/I_Kur "
      "and simplified Koivumaki 2011 Ca handling. Variants: colman2013 (default), ni2017 (Ni et al. 2017 "
      "updated model exactly as Myokit ni-2017.mmt), brocklehurst2022_tissue (colman2013 with a "
      "stretch-activated current active at rest, calibrated to the seed paper's tissue RMP), "
      "colman2013_caf (colman2013 with Colman 2013's chronic-AF remodelling).";
  info_.reference =
      "Colman MA et al. J Physiol 591:4249-4272 (2013); Ni H et al. Front Physiol 8:946 (2017); "
      "Courtemanche M et al. Am J Physiol 275:H301 (1998); Maleckar MM et al. Am J Physiol 297:H1398 (2009); "
      "Koivumaki JT et al. PLoS Comput Biol 7:e1001067 (2011); Myokit models c/ni-2017.mmt (M. Clerx)";
  info_.kind = fibrodem::ModelKind::ionic;

#define COLMAN_STATE_INFO(name, unit, init, lo, hi, gate) \
  info_.states.push_back({#name, unit, init, lo, hi, gate});
  COLMAN_STATES(COLMAN_STATE_INFO)
#undef COLMAN_STATE_INFO
  // Gates whose rates depend only on V and the parameters (fca and the RyR gates
  // depend on Ca; the I_Kur formulation switch is a parameter).
  for (int k : {k_m, k_h, k_j, k_d, k_f, k_xr, k_xs, k_ito_r, k_ito_s, k_ikur_a, k_ikur_i})
    info_.states[k].voltage_only = true;
#define COLMAN_PARAM_INFO(name, unit, def, desc) info_.parameters.push_back({#name, unit, def, desc});
  COLMAN_PARAMS(COLMAN_PARAM_INFO)
#undef COLMAN_PARAM_INFO

  info_.inputs = {{"i_ext", "pA", "stimulus and gap-junction current, + depolarising"},
                  {"J_TRPN", "mM/ms", "Ca binding flux to a myofilament model's troponin (calcium feedback)"}};
  info_.outputs = {
      {"I_ion", "pA", "total ionic current, + outward"},
      {"Ca_i", "mM", "bulk cytosolic Ca"},
      {"Ca_ss", "mM", "junctional subspace Ca"},
      {"INa", "pA", "fast Na current"},
      {"Ito", "pA", "transient outward K current"},
      {"IKur", "pA", "ultrarapid delayed rectifier K current"},
      {"IKr", "pA", "rapid delayed rectifier K current"},
      {"IKs", "pA", "slow delayed rectifier K current"},
      {"ICaL", "pA", "L-type Ca current"},
      {"IK1", "pA", "inward rectifier K current"},
      {"INaCa", "pA", "Na/Ca exchanger current"},
      {"INaK", "pA", "Na/K pump current"},
      {"ISAC", "pA", "stretch-activated non-selective cation current (brocklehurst2022_tissue)"},
  };
  info_.voltage_state = k_V;
  info_.capacitance_parameter = k_Cm_pF;

  fibrodem::VariantInfo colman2013{
      "colman2013",
      "Colman et al. 2013 right atrium (default), as the authors' committed original-Colman 1 Hz "
      "trace shows it: Maleckar I_to (g 0.1962) and I_Kur, I_CaL 2.125*0.1294, CRN I_Kr/I_Ks and "
      "background/pump currents, I_ab, clamped Na_i and K_i, Koivumaki RyR time constants; "
      "SERCA_bulk_const and ICaL_f_tau_scale fitted to that trace; initial state = 1 Hz steady "
      "state of this variant.",
      {},
      {}};
  fibrodem::VariantInfo ni2017{
      "ni2017",
      "Ni et al. 2017 updated CNZ model, right atrium, exactly as Myokit ni-2017.mmt (quirks G1, G2, "
      "constant K_i kept); initial state = ni-2017.mmt.",
      {},
      {}};
  for (const Override& o : kNi2017Params) {
    for (const fibrodem::ParameterInfo& p : info_.parameters) {
      if (p.name == o.name) colman2013.parameters[p.name] = p.default_value;
    }
    ni2017.parameters[o.name] = o.ni2017;
  }
  for (const fibrodem::StateInfo& s : info_.states) colman2013.initial_state[s.name] = s.initial;
  for (const auto& [name, value] : kNi2017Initial) ni2017.initial_state[name] = value;
  fibrodem::VariantInfo brocklehurst{
      "brocklehurst2022_tissue",
      "colman2013 with the stretch-activated non-selective cation current I_SAC active at rest "
      "(the seed paper's myocyte, Brocklehurst et al. 2022 2.1.1): g_SAC calibrated to the paper's "
      "tissue myocyte RMP (-65.2 mV at F-M 0.11, D_f 0.3 nS, in-series), E_SAC -6.1 mV; initial "
      "state = its own rest (60 s unpaced).",
      colman2013.parameters,
      {}};
  brocklehurst.parameters["g_SAC_nS_per_pF"] = kBrocklehurstGSac_nS_per_pF;
  for (const auto& [name, value] : kBrocklehurstInitial) brocklehurst.initial_state[name] = value;
  fibrodem::VariantInfo caf{
      "colman2013_caf",
      "colman2013 with the chronic-AF electrical remodelling of Colman et al. 2013 (set AF_Col_4: "
      "g_CaL x0.3, g_to x0.34, g_Kur x0.5, g_K1 x2, g_Ks x2, I_NaCa x1.55, SR leak x1.25, RyR "
      "release x3); initial state = its own 1 Hz steady state.",
      colman2013.parameters,
      {}};
  for (const auto& [name, value] : kColman2013CafScales) caf.parameters[name] = value;
  for (const auto& [name, value] : kColman2013CafInitial) caf.initial_state[name] = value;
  info_.variants = {colman2013, ni2017, brocklehurst, caf};
}

}  // namespace

FIBRODEM_CELL_MODEL_PLUGIN(Colman)
