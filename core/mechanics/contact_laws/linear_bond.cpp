// `linear_bond`: PFC's linear contact bond with dashpots (REFERENCES.md 2.2-2.3;
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
#include <algorithm>
#include <cmath>

#include "mechanics/contact_law.hpp"

namespace fibrodem {
namespace {

class LinearBond final : public ContactLaw {
 public:
  explicit LinearBond(const DemSpec& s)
      : beta_n_(s.damping_ratio_normal),
        beta_s_(s.damping_ratio_shear),
        tensile_(s.tensile_strength_N),
        shear_(s.shear_strength_N),
        mu_(s.friction) {}

  std::string name() const override { return "linear_bond"; }

  void prepare(BondSet& b) const override {
    for (std::size_t i = 0; i < b.size(); ++i) {
      b.cn[i] = 2 * beta_n_ * std::sqrt(b.m_eff[i] * b.kn[i]);
      b.cs[i] = 2 * beta_s_ * std::sqrt(b.m_eff[i] * b.ks[i]);
    }
  }

  void update(BondSet& b, const BondBlock& blk, double dt) const override {
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
        if (-n >= tensile_) {  // tensile failure: forces zeroed
          intact[i] = 0;
          n = 0;
          s = 0;
        } else if (std::abs(s) >= shear_) {  // shear failure
          intact[i] = 0;
          const double cap = n > 0 ? mu_ * n : 0.0;
          if (std::abs(s) > cap) s = std::copysign(cap, s);
        }
        fn[i] = n;
        fs[i] = s;
        blk.fn_total[i] = n - cn[i] * blk.dn[i] * inv_dt;
        blk.fs_total[i] = s - cs[i] * blk.ds[i] * inv_dt;
      } else if (overlap >= 0) {  // broken bond, particles in contact
        const double n = kn[i] * overlap;
        double s = fs[i] - ks[i] * blk.ds[i];
        const double cap = mu_ * n;
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

  double stable_step_stiffness(double k, bool shear) const override {
    const double beta = shear ? beta_s_ : beta_n_;
    const double f = std::sqrt(1 + beta * beta) - beta;
    return k / (f * f);
  }

 private:
  double beta_n_, beta_s_, tensile_, shear_, mu_;
};

}  // namespace

std::unique_ptr<ContactLaw> make_linear_bond_law(const DemSpec& spec) {
  return std::make_unique<LinearBond>(spec);
}

}  // namespace fibrodem
