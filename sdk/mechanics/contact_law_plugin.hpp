// The plugin contract between the fibrodem core and a contact law of the DEM
// mechanics, in the style of LAMMPS' granular sub-models and PFC's contact
// models (docs/reference/references.md#dem-contact-laws). Header-only, like cell_model.hpp: a law
// links nothing of the core.
//
// The DEM solver keeps the contacts in structure-of-arrays (BondSet) and calls
// the law once per block of contacts (no virtual call per contact): it fills
// the block's kinematics (gap, increments over the step), the law updates the
// contacts' spring forces and writes the total forces (springs + dashpots).
//
// A law declares its parameters like a cell model (name, unit, default,
// description); the manifest sets them in `mechanics.contact_law_parameters`
// and every call gets their values, in the declared order, as `params`. A law
// keeps no state of its own: the same call may come from several threads on
// disjoint blocks.
//
// Conventions (2D, SI): n points from particle p to particle q, t = (-n_y, n_x);
// gap = |x_q - x_p| - (r_p + r_q) (< 0: overlap); increments are of q relative to
// p at the contact point, normal > 0 opening. Forces act on q (minus on p):
// f_q = F_n n + F_s t, F_n > 0 compression.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "model/cell_model.hpp"  // ParameterInfo

namespace fibrodem {

// Bumped whenever anything in this header changes layout or meaning.
inline constexpr int kContactLawAbiVersion = 1;

// Contacts in SoA, one entry per pair: the tissue's bonds, or the unbonded
// contacts found by detection (intact 0 from the start, reference gap 0: a
// plain contact). The constants are set by the solver (stiffness after
// inheritance and the fibroblast factor, effective mass, reference gap,
// bending stiffness from the law's bending_stiffness) and by the law's
// prepare(); the state (fn, fs, mb, intact) is initialised by the solver and
// updated by the law's update().
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
  void resize(std::size_t n) {
    for (auto* v : {&p, &q}) v->resize(n);
    for (auto* v : {&kn, &ks, &m_eff, &ref_gap, &cn, &cs, &kb, &fn, &fs, &mb}) v->resize(n);
    intact.resize(n);
  }
};

// Kinematics of one block of contacts [begin, begin + count) of a BondSet,
// filled by the solver, and the total forces the law returns for it (arrays
// indexed 0 .. count-1; the BondSet's from begin).
struct BondBlock {
  std::size_t begin = 0, count = 0;
  const double* gap = nullptr;     // m
  const double* dn = nullptr;      // m, normal increment over the step (opening > 0)
  const double* ds = nullptr;      // m, shear increment over the step
  const double* dtheta = nullptr;  // rad, rotation of q relative to p over the step
  double* fn_total = nullptr;      // N, normal force on q (compression > 0), springs + dashpots
  double* fs_total = nullptr;      // N, shear force on q along t
  double* m_total = nullptr;       // N m, moment on q (minus on p); zeroed by the solver, set by laws with bending
};

struct ContactLawInfo {
  std::string name;
  std::string version;
  std::string description;
  std::string reference;  // where the law comes from
  std::vector<ParameterInfo> parameters;
};

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;
  virtual const ContactLawInfo& info() const = 0;
  // Sets the per-contact constants the law needs (e.g. dashpot coefficients)
  // once kn, ks and m_eff are known; leaves the state alone.
  virtual void prepare(BondSet& bonds, const double* params) const = 0;
  // Updates the contacts of one block over a step of dt [s] (may break bonds)
  // and writes the block's total forces (and moments, for laws with bending).
  // Must not allocate or throw.
  virtual void update(BondSet& bonds, const BondBlock& block, const double* params, double dt_s) const = 0;
  // The stiffness [N/m] that sets the stable step for a contact of stiffness k
  // (normal: shear = false), including the law's dashpot correction; for a
  // nonlinear law, its largest tangent stiffness over the overlaps expected.
  virtual double stable_step_stiffness(double k, bool shear, const double* params) const = 0;
  // The bending stiffness [N m/rad] of a bond of normal stiffness kn between
  // particles of radii r_p, r_q [m]; 0 for laws that transmit no moment.
  virtual double bending_stiffness(double /*kn*/, double /*r_p*/, double /*r_q*/, const double* /*params*/) const {
    return 0;
  }
};

}  // namespace fibrodem

// Each contact-law plugin library defines exactly one law with this macro.
#define FIBRODEM_CONTACT_LAW_PLUGIN(LawClass)                                                 \
  extern "C" __attribute__((visibility("default"))) int fibrodem_contact_law_abi_version() { \
    return ::fibrodem::kContactLawAbiVersion;                                               \
  }                                                                                         \
  extern "C" __attribute__((visibility("default"))) const char* fibrodem_stdlib_abi() {     \
    return ::fibrodem::kStdlibAbi;                                                          \
  }                                                                                         \
  extern "C" __attribute__((visibility("default")))                                         \
  ::fibrodem::ContactLaw* fibrodem_create_contact_law() {                                   \
    return new LawClass();                                                                  \
  }
