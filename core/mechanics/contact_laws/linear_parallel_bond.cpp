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
#include <memory>

#include "mechanics/contact_law.hpp"

namespace fibrodem {
namespace {

class LinearParallelBond final : public ContactLaw {
 public:
  explicit LinearParallelBond(const DemSpec& s)
      : forces_(make_linear_bond_law(s)), multiplier_(s.bond_radius_multiplier) {}

  std::string name() const override { return "linear_parallel_bond"; }
  void prepare(BondSet& bonds) const override { forces_->prepare(bonds); }

  void update(BondSet& b, const BondBlock& blk, double dt) const override {
    forces_->update(b, blk, dt);
    double* const mb = b.mb.data() + blk.begin;
    const double* const kb = b.kb.data() + blk.begin;
    const std::uint8_t* const intact = b.intact.data() + blk.begin;
#pragma omp simd
    for (std::size_t i = 0; i < blk.count; ++i) {
      mb[i] = intact[i] ? mb[i] - kb[i] * blk.dtheta[i] : 0.0;
      blk.m_total[i] = mb[i];
    }
  }

  double stable_step_stiffness(double k, bool shear) const override {
    return forces_->stable_step_stiffness(k, shear);
  }

  double bending_stiffness(double kn, double r_p, double r_q) const override {
    const double R = multiplier_ * std::min(r_p, r_q);
    return kn * R * R / 3;
  }

 private:
  std::unique_ptr<ContactLaw> forces_;
  double multiplier_;
};

}  // namespace

std::unique_ptr<ContactLaw> make_linear_parallel_bond_law(const DemSpec& spec) {
  return std::make_unique<LinearParallelBond>(spec);
}

}  // namespace fibrodem
