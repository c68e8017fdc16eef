// A contact law written as an out-of-tree author would (it sees only the
// plugin SDK: built with fibrodem_add_contact_law against fibrodem::plugin_sdk,
// into build/test_plugins): Hertz's normal contact of two elastic spheres,
//   F_n = (4/3) E* sqrt(R*) d^(3/2)   for an overlap d = g_ref - g > 0, else 0
// (Johnson, Contact Mechanics 1985, eq. 4.23), no tension, no shear, no
// dashpot. E* and R* are parameters (the law sees no radii). The test checks
// its forces against the formula.
#include <cmath>

#include "mechanics/contact_law_plugin.hpp"

namespace {

enum Param { kModulus_Pa, kRadius_um, kMaxOverlap_um };

class HertzNormal final : public fibrodem::ContactLaw {
 public:
  HertzNormal() {
    info_.name = "hertz_normal";
    info_.version = "test";
    info_.description = "Hertz normal contact (test law)";
    info_.reference = "Johnson KL, Contact Mechanics (1985), eq. 4.23";
    info_.parameters = {
        {"effective_modulus_Pa", "Pa", 1.0e4, "E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)"},
        {"effective_radius_um", "um", 5.0, "R* = r1 r2 / (r1 + r2)"},
        {"max_overlap_um", "um", 2.0, "largest overlap expected (sets the stable step)"},
    };
  }
  const fibrodem::ContactLawInfo& info() const override { return info_; }
  void prepare(fibrodem::BondSet&, const double*) const override {}
  void update(fibrodem::BondSet& b, const fibrodem::BondBlock& blk, const double* params, double) const override {
    const double stiffness = 4.0 / 3.0 * params[kModulus_Pa] * std::sqrt(params[kRadius_um] * 1e-6);
    for (std::size_t j = 0; j < blk.count; ++j) {
      const std::size_t i = blk.begin + j;
      const double d = b.ref_gap[i] - blk.gap[j];
      const double fn = d > 0 ? stiffness * d * std::sqrt(d) : 0.0;
      b.fn[i] = fn;
      b.fs[i] = 0;
      b.intact[i] = 0;
      blk.fn_total[j] = fn;
      blk.fs_total[j] = 0;
    }
  }
  // dF/dd = 2 E* sqrt(R* d) at the largest overlap expected.
  double stable_step_stiffness(double, bool shear, const double* params) const override {
    if (shear) return 0;
    return 2 * params[kModulus_Pa] * std::sqrt(params[kRadius_um] * params[kMaxOverlap_um]) * 1e-6;
  }

 private:
  fibrodem::ContactLawInfo info_;
};

}  // namespace

FIBRODEM_CONTACT_LAW_PLUGIN(HertzNormal)
