// The parameters of the DEM tissue mechanics (manifest `mechanics` object),
// with the seed paper's Table 1 as defaults (docs/reference/references.md#seed-paper,
// docs/reference/references.md#dem).
// Units at this boundary: N/m, N, kg/m^3, ms; inside the solver SI.
#pragma once

#include <map>
#include <string>

#include "util/json_reader.hpp"

namespace fibrodem {

// How a contracting myocyte clump keeps its 2D area
// (docs/reference/references.md#dem-contraction-rule).
enum class AreaRule {
  union_area,  // (A) area of the union of the disks (Newton on r)
  capsule,     // (B) 2r(N-1)s + pi r^2 = const
  rectangle,   // (C) r (N-1) s = const, i.e. r = r0 s0 / s
};
// How the cell's length ratio lambda = L/L0 sets the clump's geometry.
enum class LengthMode {
  spacing,  // particle spacing s = s0 lambda (docs/reference/references.md#dem-contraction-rule); r from the area rule
  total,    // total length (N-1)s + 2r = lambda L0 with the area kept (both s and r solved)
};
// Which velocities the tissue strain is fitted to
// (docs/reference/references.md#dem-strain-by-best-fit).
enum class StrainBodies {
  particles,  // every particle (pebbles of clumps and fibroblast disks): the seed's "all particles"
  bodies,     // clump centroids and fibroblast disks
};
// How a contact's stiffness follows from kn, ks (stiffness inheritance,
// docs/reference/references.md#dem-contact-laws).
enum class StiffnessInheritance {
  contact,  // kn, ks are the contact's (PFC contact-model property): 26 N/m per bond
  series,   // kn, ks set on both particles, springs in series: kn/2 per bond
};

struct DemSpec {
  std::string solver = "dem";
  std::string contact_law = "linear_bond";  // a contact-law plugin (contact_law_plugin.hpp)
  // Values of the law's declared parameters by name (manifest
  // `contact_law_parameters`); the rest keep their defaults, or the values of
  // the keys below of the same names (contact_law.hpp).
  std::map<std::string, double> contact_law_parameters;
  double kn_N_per_m = 26.0;               // Table 1
  double ks_N_per_m = 0.26;               // Table 1
  double damping_ratio_normal = 0.1;      // beta_n, Table 1
  double damping_ratio_shear = 0.1;       // beta_s, Table 1
  double tensile_strength_N = 1e200;      // T_F, Table 1 (a force, PFC cb_tenf)
  double shear_strength_N = 1e200;        // S_F, Table 1 (a force, PFC cb_shearf)
  double friction = 0.0;                  // Coulomb coefficient of a broken bond's contact
  // PFC's local damping: each body's force and moment reduced by alpha |F| in
  // the direction against its velocity (docs/reference/references.md#dem-motion-and-2d-bodies: default 0 in PFC 5+,
  // 0.7 in PFC 4; the seed lists only the dashpots).
  double local_damping = 0.0;
  double fibroblast_stiffness_factor = 1.0;  // kn, ks x this if either end is a fibroblast (seed: 1.5)
  // kn, ks x this for contacts with collagen particles and bonds through
  // collagen (fibrotic_sheet's `collagen: particles`): the ratio of Young's
  // moduli of scar and myocardium, 55 / 18 kPa (Berry et al. 2006, Am J
  // Physiol Heart Circ Physiol 290:H2196, AFM of infarct scar and normal rat
  // myocardium); a contact of two equal disks of unit thickness has kn
  // proportional to E (PFC's deformability: kn = E* A / L = E* t), so the same
  // disks of scar are stiffer by that ratio.
  double collagen_stiffness_factor = 55.0 / 18.0;
  // `linear_parallel_bond` only: the bond's half-width R = this x min(r_p, r_q)
  // (PFC's pb_rmul), which sets its bending stiffness kn R^2 / 3.
  double bond_radius_multiplier = 1.0;
  StiffnessInheritance stiffness_inheritance = StiffnessInheritance::contact;
  double density_kg_per_m3 = 1053.0;      // Table 1: 1.053 g/ml; 2D disks of unit thickness (1 m)
  double safety_factor = 0.8;             // stable step = safety x min t_crit
  // Mass (density) scaling for quasi-static loading: at most this fraction of
  // the tissue's mass (and inertia) added to its lightest, stiffest bodies to
  // lengthen the stable step (dem_solver.hpp, "Stable step"); 0: none.
  double mass_scaling = 0.0;
  // Multirate stepping: bodies whose critical step is below the clumps'
  // take substeps of the step (dem_solver.hpp, "Multirate"); false: one step for all.
  bool multirate = false;
  // The coupling does not step the DEM while the tissue is at rest and the
  // cells' lengths stay as it last saw them (run/mechanics_coupling.hpp,
  // "Rest"); false: every step is taken.
  bool skip_at_rest = true;
  double dt_ms = 0.0;                     // 0 = automatic (the stable step)
  AreaRule area_rule = AreaRule::union_area;
  LengthMode length_mode = LengthMode::total;  // the seed: SL "scaled to give the total myocyte length"
  bool fibroblasts_fixed = false;         // true: fibroblast particles never move
  StrainBodies strain_bodies = StrainBodies::particles;
  // New contacts between particles not bonded at the start (PFC detects them;
  // docs/reference/references.md#dem-contact-detection): the linear contact model (the law's unbonded state).
  bool contact_detection = true;
  double contact_skin_um = 2.5;           // Verlet skin: a fifth of a myocyte pebble's radius
};

// Reads the keys of a `mechanics` object (all optional; defaults as above):
// solver, contact_law (loaded from the plugin search path to check it and its
// contact_law_parameters), contact_law_parameters, kn_N_per_m, ks_N_per_m, damping_ratio_normal,
// damping_ratio_shear, tensile_strength_N, shear_strength_N, friction, local_damping,
// fibroblast_stiffness_factor, collagen_stiffness_factor, bond_radius_multiplier, stiffness_inheritance (contact|series),
// density_kg_per_m3, safety_factor, mass_scaling, multirate, skip_at_rest, dt_ms, area_rule (union|capsule|rectangle),
// length_mode (spacing|total), fibroblasts_fixed, strain_bodies
// (particles|bodies), contact_detection, contact_skin_um. Errors name the JSON path. Does not call finish(): the
// caller may read its own keys (e.g. output rates) from the same object first.
DemSpec read_dem_spec(JsonReader& mechanics);

const char* area_rule_name(AreaRule rule);
const char* length_mode_name(LengthMode mode);

}  // namespace fibrodem
