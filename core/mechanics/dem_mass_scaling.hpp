// The DEM's mass scaling (spec `mass_scaling` f > 0; dem_solver.hpp, "Stable
// step"): PFC's density scaling for quasi-static loading (Itasca PFC 6,
// "Timestep Determination"). Every body whose critical step is below a
// target H gets the mass kt H^2 (and inertia kr H^2), with each contact
// list; H is set once, on the contacts at the start, the longest for which
// the mass (and the inertia) so added is at most f of the tissue's.
#pragma once

#include <cstddef>
#include <vector>

#include "mechanics/dem_bodies.hpp"

namespace fibrodem {

class DemMassScaling {
 public:
  // f: the spec's mass_scaling (0: none); the target critical step H at most
  // longest_s (the longest stable step over the safety factor).
  DemMassScaling(double f, double longest_s) : f_(f), longest_s_(longest_s) {}
  // The bodies' masses and inertias of motion for H on the stiffnesses on
  // them (H set on the first call); a no-op without scaling.
  void apply(DemBodies& bodies, const std::vector<double>& body_kt, const std::vector<double>& body_kr);
  // True once it has set masses (a checkpoint carries them then).
  bool active() const { return target_step_s_ > 0; }

  std::size_t scaled_bodies() const { return scaled_bodies_; }
  double added_mass_fraction() const { return added_mass_fraction_; }
  double added_inertia_fraction() const { return added_inertia_fraction_; }

 private:
  double target_step_s(const DemBodies& bodies, const std::vector<double>& body_kt,
                       const std::vector<double>& body_kr) const;

  double f_, longest_s_;
  double target_step_s_ = 0;  // H (0: none yet)
  std::size_t scaled_bodies_ = 0;
  double added_mass_fraction_ = 0, added_inertia_fraction_ = 0;
};

}  // namespace fibrodem
