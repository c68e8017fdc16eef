// Contact laws in the core: a law is a plugin (mechanics/contact_law_plugin.hpp,
// file libfibrodem_contact_law_<name>.so on the plugin search path; the
// bundled ones are plugins/linear_bond and plugins/linear_parallel_bond),
// bound here to the parameter values of a scene.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mechanics/contact_law_plugin.hpp"
#include "mechanics/dem_spec.hpp"

namespace fibrodem {

class PluginRegistry;

// A law with its parameter values: what the DEM solver calls (one virtual
// call into the plugin per block of contacts).
class BoundContactLaw {
 public:
  BoundContactLaw(std::shared_ptr<const ContactLaw> law, std::vector<double> params)
      : law_(std::move(law)), params_(std::move(params)) {}

  const std::string& name() const { return law_->info().name; }
  const ContactLaw& law() const { return *law_; }
  const std::vector<double>& parameters() const { return params_; }

  void prepare(BondSet& bonds) const { law_->prepare(bonds, params_.data()); }
  void update(BondSet& bonds, const BondBlock& block, double dt_s) const {
    law_->update(bonds, block, params_.data(), dt_s);
  }
  double stable_step_stiffness(double k, bool shear) const {
    return law_->stable_step_stiffness(k, shear, params_.data());
  }
  double bending_stiffness(double kn, double r_p, double r_q) const {
    return law_->bending_stiffness(kn, r_p, r_q, params_.data());
  }

 private:
  std::shared_ptr<const ContactLaw> law_;
  std::vector<double> params_;
};

// Loads (once per process) the contact law `name` from the plugin search path
// (PluginRegistry::default_search_path(), read again for a name not loaded
// yet); throws PluginError naming the search path and the laws found.
std::shared_ptr<const ContactLaw> load_contact_law(const std::string& name);
// Where a loaded law came from (for summary.json), by name; throws
// PluginError for a law not loaded.
struct ContactLawRecord {
  std::string name, version, file, sha256;
};
ContactLawRecord contact_law_record(const std::string& name);
// The names of the contact laws on the default search path.
std::vector<std::string> available_contact_laws();
// Each of them loaded and described (what `fibrodem plugins` lists): name,
// version, description, reference, file, sha256, parameters (name, unit,
// default, description). A law that cannot be loaded is left out and its
// error appended to `errors`.
nlohmann::json describe_available_contact_laws(std::vector<std::string>& errors);

// The parameter values of `law` for a scene: its defaults; then the
// `mechanics` keys that predate law plugins (damping_ratio_normal,
// damping_ratio_shear, tensile_strength_N, shear_strength_N, friction,
// bond_radius_multiplier) for the law's parameters of those names; then
// spec.contact_law_parameters. Throws std::invalid_argument for a name the law
// does not declare or a value that is not finite.
std::vector<double> contact_law_parameter_values(const ContactLawInfo& law, const DemSpec& spec);

// The spec's law (loaded by name) with the spec's parameter values.
std::unique_ptr<BoundContactLaw> make_contact_law(const DemSpec& spec);

}  // namespace fibrodem
