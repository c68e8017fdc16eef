// A ContactLaw turns the kinematics of one particle contact into forces, in
// the style of LAMMPS' granular sub-models and PFC's contact models
// (REFERENCES.md section 2.2-2.3). Laws are small classes registered by name
// (`linear_bond`: the seed paper's Table 1) and composed by the DEM force loop.
//
// Interface only for now: the DEM solver that uses it is a later issue.
#pragma once

#include <string>

namespace fibrodem {

// The state of one contact the law reads and updates (2D, SI units inside DEM).
struct ContactState {
  double gap_m = 0;            // d - (R1 + R2); negative = overlap
  double reference_gap_m = 0;  // the bond's gap at formation (bonds are not pre-loaded)
  double normal_increment_m = 0;  // opening positive, over this step
  double shear_increment_m = 0;
  double effective_mass_kg = 0;
  double dt_s = 0;
  double normal_force_N = 0;   // positive = compression
  double shear_force_N = 0;    // stored in the contact frame (incremental)
  bool bonded = true;
};

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;
  virtual std::string name() const = 0;
  // Updates the forces of one contact; may break its bond.
  virtual void update(ContactState& contact) const = 0;
  // Largest normal and shear stiffness [N/m], for the stable time step.
  virtual double max_stiffness_N_per_m() const = 0;
};

}  // namespace fibrodem
