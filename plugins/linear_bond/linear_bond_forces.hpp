// `linear_bond`: PFC's linear contact bond with dashpots (docs/reference/references.md#dem-contact-laws;
// seed paper Table 1), as the seed paper's DEM used it:
// - bonded: F_n = kn (g_ref - g), absolute against the bond's reference gap g_ref
//   (the gap at formation, so bonds start unloaded; tension allowed), F_s
//   incremental in the contact frame, F_s -= ks ds, no Coulomb cap;
// - breaks when the tension -F_n >= tensile strength (forces zeroed) or |F_s| >=
//   shear strength (F_s kept up to mu F_n if compressive, else zeroed);
// - broken, or a contact found by detection (PFC's linear model): active while g <= g_ref, F_n = max(0, .),
//   |F_s| <= mu F_n; inactive: forces zero, shear history reset;
// - dashpots c = 2 beta sqrt(m_eff k), F_d = -c (increment / dt), added to the
//   springs' forces (normal dashpot only while the contact is active).
// The stable step uses k / (sqrt(1 + beta^2) - beta)^2 (Itasca's plugin example).
//
// Shared by the plugins linear_bond and linear_parallel_bond (which adds a
// bending moment): their first five parameters are these, in this order.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "mechanics/contact_law_plugin.hpp"

namespace fibrodem::linear_bond {

enum Param { kDampingNormal, kDampingShear, kTensileStrength_N, kShearStrength_N, kFriction, kParamCount };

// The seed paper's Table 1 (damping ratios 0.1, strengths 1e200 N: bonds
// never break) and no friction; the names are those of the `mechanics` keys
// that set them before laws were plugins.
inline std::vector<ParameterInfo> parameters() {
  return {
      {"damping_ratio_normal", "1", 0.1, "beta_n: normal dashpot, fraction of critical damping (Table 1)"},
      {"damping_ratio_shear", "1", 0.1, "beta_s: shear dashpot, fraction of critical damping (Table 1)"},
      {"tensile_strength_N", "N", 1e200, "T_F: tension at which a bond breaks (PFC cb_tenf; Table 1)"},
      {"shear_strength_N", "N", 1e200, "S_F: shear force at which a bond breaks (PFC cb_shearf; Table 1)"},
      {"friction", "1", 0.0, "Coulomb coefficient of a broken bond's or an unbonded contact"},
  };
}

inline void prepare(BondSet& b, const double* params) {
  const double beta_n = params[kDampingNormal], beta_s = params[kDampingShear];
  for (std::size_t i = 0; i < b.size(); ++i) {
    b.cn[i] = 2 * beta_n * std::sqrt(b.m_eff[i] * b.kn[i]);
    b.cs[i] = 2 * beta_s * std::sqrt(b.m_eff[i] * b.ks[i]);
  }
}

inline void update(BondSet& b, const BondBlock& blk, const double* params, double dt) {
  const double tensile = params[kTensileStrength_N], shear = params[kShearStrength_N], mu = params[kFriction];
  const double inv_dt = 1 / dt;
  double* const fn = b.fn.data() + blk.begin;
  double* const fs = b.fs.data() + blk.begin;
  const double* const kn = b.kn.data() + blk.begin;
  const double* const ks = b.ks.data() + blk.begin;
  const double* const cn = b.cn.data() + blk.begin;
  const double* const cs = b.cs.data() + blk.begin;
  const double* const ref = b.ref_gap.data() + blk.begin;
  std::uint8_t* const intact = b.intact.data() + blk.begin;
  for (std::size_t i = 0; i < blk.count; ++i) {
    const double overlap = ref[i] - blk.gap[i];
    if (intact[i]) {
      double n = kn[i] * overlap;
      double s = fs[i] - ks[i] * blk.ds[i];
      if (-n >= tensile) {  // tensile failure: forces zeroed
        intact[i] = 0;
        n = 0;
        s = 0;
      } else if (std::abs(s) >= shear) {  // shear failure
        intact[i] = 0;
        const double cap = n > 0 ? mu * n : 0.0;
        if (std::abs(s) > cap) s = std::copysign(cap, s);
      }
      fn[i] = n;
      fs[i] = s;
      blk.fn_total[i] = n - cn[i] * blk.dn[i] * inv_dt;
      blk.fs_total[i] = s - cs[i] * blk.ds[i] * inv_dt;
    } else if (overlap >= 0) {  // broken bond, particles in contact
      const double n = kn[i] * overlap;
      double s = fs[i] - ks[i] * blk.ds[i];
      const double cap = mu * n;
      if (std::abs(s) > cap) s = std::copysign(cap, s);
      fn[i] = n;
      fs[i] = s;
      blk.fn_total[i] = n - cn[i] * blk.dn[i] * inv_dt;
      blk.fs_total[i] = s - cs[i] * blk.ds[i] * inv_dt;
    } else {
      fn[i] = 0;
      fs[i] = 0;
      blk.fn_total[i] = 0;
      blk.fs_total[i] = 0;
    }
  }
}

inline double stable_step_stiffness(double k, bool shear, const double* params) {
  const double beta = shear ? params[kDampingShear] : params[kDampingNormal];
  const double f = std::sqrt(1 + beta * beta) - beta;
  return k / (f * f);
}

}  // namespace fibrodem::linear_bond
