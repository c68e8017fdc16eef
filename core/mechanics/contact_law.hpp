// A ContactLaw turns the kinematics of particle contacts into forces, in the
// style of LAMMPS' granular sub-models and PFC's contact models (REFERENCES.md
// 2.2-2.3). Laws are small classes, one per file in contact_laws/, registered
// by name in contact_laws() (`linear_bond`: the seed paper's Table 1).
//
// The DEM solver keeps the bonds in structure-of-arrays (BondSet) and calls the
// law once per block of bonds (no virtual call per contact): it fills the
// block's kinematics (gap, increments over the step), the law updates the
// bonds' spring forces and writes the total forces (springs + dashpots).
//
// Conventions (2D, SI): n points from particle p to particle q, t = (-n_y, n_x);
// gap = |x_q - x_p| - (r_p + r_q) (< 0: overlap); increments are of q relative to
// p at the contact point, normal > 0 opening. Forces act on q (minus on p):
// f_q = F_n n + F_s t, F_n > 0 compression.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mechanics/dem_spec.hpp"

namespace fibrodem {

// Contacts in SoA, one entry per pair: the tissue's bonds, or the unbonded
// contacts found by detection (intact 0 from the start, reference gap 0: a
// plain linear contact, PFC's linear model). The constants are set by the
// solver (stiffness after inheritance and the fibroblast factor, effective
// mass, reference gap) and by the law's prepare(); the state (fn, fs, intact)
// is initialised by the solver and updated by update().
struct BondSet {
  std::vector<int> p, q;              // particle indices
  std::vector<double> kn, ks;         // N/m
  std::vector<double> m_eff;          // kg, m_p m_q / (m_p + m_q) of the bodies (clump masses for pebbles)
  std::vector<double> ref_gap;        // m, the gap at formation (bonds are not pre-loaded)
  std::vector<double> cn, cs;         // N s/m, dashpot coefficients (law's prepare())
  std::vector<double> kb;             // N m/rad, bending stiffness (laws with bending; 0 for contacts)
  std::vector<double> fn, fs;         // N, spring forces (state; shear in the contact frame)
  std::vector<double> mb;             // N m, bending moment on q (state; laws with bending)
  std::vector<std::uint8_t> intact;   // 1 while the bond holds (a broken bond is a plain contact)
  std::size_t size() const { return p.size(); }
  void resize(std::size_t n);
};

// Kinematics of one block of bonds [begin, begin + count), filled by the
// solver, and the total forces the law returns for it.
struct BondBlock {
  std::size_t begin = 0, count = 0;
  const double* gap = nullptr;   // m
  const double* dn = nullptr;    // m, normal increment over the step (opening > 0)
  const double* ds = nullptr;    // m, shear increment over the step
  const double* dtheta = nullptr;  // rad, rotation of q relative to p over the step
  double* fn_total = nullptr;    // N, normal force on q (compression > 0), springs + dashpots
  double* fs_total = nullptr;    // N, shear force on q along t
  double* m_total = nullptr;     // N m, moment on q (minus on p); zeroed by the solver, set by laws with bending
};

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;
  virtual std::string name() const = 0;
  // Sets the per-contact constants the law needs (e.g. dashpot coefficients)
  // once kn, ks and m_eff are known; leaves the state alone.
  virtual void prepare(BondSet& bonds) const = 0;
  // Updates the bonds of one block over a step of dt [s]; may break bonds.
  virtual void update(BondSet& bonds, const BondBlock& block, double dt_s) const = 0;
  // The stiffness [N/m] that sets the stable step for a contact of stiffness k
  // (normal: shear = false), including the law's dashpot correction.
  virtual double stable_step_stiffness(double k, bool shear) const = 0;
  // The bending stiffness [N m/rad] of a bond of normal stiffness kn between
  // particles of radii r_p, r_q [m]; 0 for laws that transmit no moment.
  virtual double bending_stiffness(double /*kn*/, double /*r_p*/, double /*r_q*/) const { return 0; }
};

using ContactLawFactory = std::unique_ptr<ContactLaw> (*)(const DemSpec&);
const std::map<std::string, ContactLawFactory>& contact_laws();
// The spec's law; throws std::invalid_argument for an unknown name.
std::unique_ptr<ContactLaw> make_contact_law(const DemSpec& spec);

// Each law's factory, defined in contact_laws/<name>.cpp.
std::unique_ptr<ContactLaw> make_linear_bond_law(const DemSpec& spec);
std::unique_ptr<ContactLaw> make_linear_parallel_bond_law(const DemSpec& spec);

}  // namespace fibrodem
