// `linear_parallel_bond`: the linear contact bond (`linear_bond`, the seed
// paper's law) plus a bending moment, as PFC's linear parallel bond adds a
// cemented beam that resists relative rotation (Potyondy & Cundall 2004). Not
// in the seed paper: a bond between two cells' ends acts there as a hinge
// (only ks = kn/100 resists rotation), which lets chains of rotated myocytes
// in interstitial tissue fold; this law asks what a bending-stiff junction
// changes.
//
// 2D, unit thickness, a bond of half-width R = bond_radius_multiplier x
// min(r_p, r_q) taken at formation: with the normal stiffness kn spread over
// its cross-section (kn/A per area, A = 2R), the moment M = -(kn/A) I dtheta,
// I = 2R^3/3, i.e. a bending stiffness kb = kn R^2 / 3, incremental in the
// relative rotation. The moment transmits while the bond is intact and drops
// to zero when it breaks (no moment-based failure: strengths as linear_bond).
// No moment dashpot (PFC's parallel bond has none); the stable step counts kb.
#include <algorithm>
#include <cstdint>

#include "linear_bond/linear_bond_forces.hpp"
#include "mechanics/contact_law_plugin.hpp"

namespace {

constexpr int kBondRadiusMultiplier = fibrodem::linear_bond::kParamCount;

class LinearParallelBond final : public fibrodem::ContactLaw {
 public:
  LinearParallelBond() {
    info_.name = "linear_parallel_bond";
    info_.version = "1.0.0";
    info_.description = "linear_bond plus a bending moment kb = kn R^2/3 (PFC's linear parallel bond)";
    info_.reference = "Potyondy & Cundall 2004, Int J Rock Mech Min Sci 41:1329 (parallel bond)";
    info_.parameters = fibrodem::linear_bond::parameters();
    info_.parameters.push_back({"bond_radius_multiplier", "1", 1.0,
                                "the bond's half-width R as a multiple of the smaller radius (PFC pb_rmul)"});
  }
  const fibrodem::ContactLawInfo& info() const override { return info_; }
  void prepare(fibrodem::BondSet& bonds, const double* params) const override {
    fibrodem::linear_bond::prepare(bonds, params);
  }

  void update(fibrodem::BondSet& b, const fibrodem::BondBlock& blk, const double* params, double dt) const override {
    fibrodem::linear_bond::update(b, blk, params, dt);
    double* const mb = b.mb.data() + blk.begin;
    const double* const kb = b.kb.data() + blk.begin;
    const std::uint8_t* const intact = b.intact.data() + blk.begin;
#pragma omp simd
    for (std::size_t i = 0; i < blk.count; ++i) {
      mb[i] = intact[i] ? mb[i] - kb[i] * blk.dtheta[i] : 0.0;
      blk.m_total[i] = mb[i];
    }
  }

  double stable_step_stiffness(double k, bool shear, const double* params) const override {
    return fibrodem::linear_bond::stable_step_stiffness(k, shear, params);
  }

  double bending_stiffness(double kn, double r_p, double r_q, const double* params) const override {
    const double R = params[kBondRadiusMultiplier] * std::min(r_p, r_q);
    return kn * R * R / 3;
  }

 private:
  fibrodem::ContactLawInfo info_;
};

}  // namespace

FIBRODEM_CONTACT_LAW_PLUGIN(LinearParallelBond)
