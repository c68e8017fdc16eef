// The contact-law plugin `linear_bond` (the seed paper's law; equations in
// linear_bond_forces.hpp).
#include "linear_bond/linear_bond_forces.hpp"
#include "mechanics/contact_law_plugin.hpp"

namespace {

class LinearBond final : public fibrodem::ContactLaw {
 public:
  LinearBond() {
    info_.name = "linear_bond";
    info_.version = "1.0.0";
    info_.description = "PFC's linear contact bond with dashpots; broken bonds and new contacts: linear contact";
    info_.reference = "Itasca PFC linear contact bond model; seed paper Table 1";
    info_.parameters = fibrodem::linear_bond::parameters();
  }
  const fibrodem::ContactLawInfo& info() const override { return info_; }
  void prepare(fibrodem::BondSet& bonds, const double* params) const override {
    fibrodem::linear_bond::prepare(bonds, params);
  }
  void update(fibrodem::BondSet& bonds, const fibrodem::BondBlock& block, const double* params,
              double dt_s) const override {
    fibrodem::linear_bond::update(bonds, block, params, dt_s);
  }
  double stable_step_stiffness(double k, bool shear, const double* params) const override {
    return fibrodem::linear_bond::stable_step_stiffness(k, shear, params);
  }

 private:
  fibrodem::ContactLawInfo info_;
};

}  // namespace

FIBRODEM_CONTACT_LAW_PLUGIN(LinearBond)
