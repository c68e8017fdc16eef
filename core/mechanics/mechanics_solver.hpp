// A MechanicsSolver moves the tissue's bodies (DEM: rigid myocyte clumps and
// fibroblast disks) under the forces of its contacts, driven by the cells'
// lengths, and reports the tissue's strain (DESIGN.md, "Interfaces").
//
// Interface only for now: the `dem` solver is a later issue.
#pragma once

#include <array>
#include <vector>

#include "mechanics/contact_law.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

class MechanicsSolver {
 public:
  virtual ~MechanicsSolver() = default;
  // The largest step [ms] at which the explicit scheme is stable (with the
  // dashpot correction and a safety factor); a larger one must be refused.
  virtual double stable_step_ms() const = 0;
  // Sets each cell's length relative to rest (1 = rest), e.g. from sarcomere length.
  virtual void set_cell_length_ratios(const std::vector<double>& ratio) = 0;
  // Advances the bodies by dt.
  virtual void step(double dt_ms) = 0;
  // The tissue's accumulated average strain: eps_xx, eps_yy, eps_xy.
  virtual std::array<double, 3> strain() const = 0;
  // Present particle positions (for snapshots).
  virtual const std::vector<Particle>& particles() const = 0;
};

}  // namespace fibrodem
