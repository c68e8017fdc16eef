// The DEM's contacts (dem_solver.hpp, "Contacts"): the tissue's bonds and
// the Verlet list of unbonded contacts (both BondSets, in SoA order), their
// law, each contact's force and moments, the indexes the force sums read
// them by, and each contact's stiffness on its bodies (the stable step's).
// The force sums per particle and body are defined in dem_step_inline.hpp,
// for the step's loops to inline.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "mechanics/contact_detector.hpp"
#include "mechanics/contact_incidence.hpp"
#include "mechanics/contact_law.hpp"
#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_spec.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// The contacts' order in each set: under multirate the fast ones (those
// touching a light body) first, each part by (p, q) ascending; without
// multirate (light null) by (p, q) ascending.
struct ContactOrder {
  const std::uint8_t* light = nullptr;  // per body
  const int* body = nullptr;            // per particle
  bool fast(int p, int q) const { return light && (light[body[p]] || light[body[q]]); }
  bool less(int p1, int q1, int p2, int q2) const {
    const bool fast1 = fast(p1, q1), fast2 = fast(p2, q2);
    if (fast1 != fast2) return fast1;
    return std::make_pair(p1, q1) < std::make_pair(p2, q2);
  }
};

// Counts every contact (DemContacts::sum_particle, sum_body).
inline constexpr auto kEveryContact = [](std::size_t) { return true; };

class DemContacts {
 public:
  static constexpr std::size_t kBlock = 512;  // contacts per call of the law

  explicit DemContacts(const DemSpec& spec);

  // The tissue's bonds and its bonds through collagen (which take
  // spec collagen_stiffness_factor), unloaded (reference gap = the gap now); throws
  // std::invalid_argument for a bond that joins invalid particles or two of
  // one clump. With contact detection, the detector, which passes them over.
  void form_bonds(const Tissue& tissue, const DemBodies& bodies);
  bool detects() const { return detector_ != nullptr; }
  // A new Verlet list at the particles' places, in `order`; a pair on the
  // old list keeps its forces.
  void rebuild_list(const DemBodies& bodies, const ContactOrder& order);
  // Both sets put in `order` (bonds: the fast ones moved first, each part in
  // its order); returns how many bonds are fast.
  std::size_t reorder(const ContactOrder& order);
  // The positions of each set's contacts in one process's order, whatever
  // `order` put them in: bonds as the tissue lists them (bond_id),
  // unbonded contacts by (p, q). What a checkpoint of a DEM split over
  // ranks holds, and the order in which its ranks trade contacts' states.
  struct TissueOrder {
    std::vector<std::size_t> bonds, contacts;
  };
  TissueOrder tissue_order() const;
  // The per-contact arrays and the incidences, after the contacts changed.
  void index(const DemBodies& bodies);
  // Each contact's stiffness on its bodies, summed per body (body_kt, body_kr).
  void stiffness_on_bodies(const DemBodies& bodies);

  // The forces of bonds [bond_begin, bond_end) and unbonded contacts
  // [contact_begin, contact_end) over a step dt_s, in blocks shared among the
  // threads: called by every thread of a parallel region.
  void forces_of_range(const DemBodies& bodies, std::size_t bond_begin, std::size_t bond_end,
                       std::size_t contact_begin, std::size_t contact_end, double dt_s);
  // Particle i's force and moment from those of its contacts `counted` takes
  // (a contact's index -> bool), and body b's about (gx, gy)
  // (dem_step_inline.hpp).
  template <class Counted>
  void sum_particle(std::size_t i, Counted counted, double& fx, double& fy, double& tq) const;
  template <class Counted>
  void sum_body(const DemBodies& bodies, std::size_t b, double gx, double gy, Counted counted,
                double (&f)[3]) const;

  // Counted over every contact, or (given `own_of`) over those whose
  // particle p's body that rank steps (DemBodies::steps: a split DEM's own).
  std::size_t broken_bonds(const DemBodies* own_of = nullptr) const;
  std::size_t touching_contacts(const DemBodies* own_of = nullptr) const;
  std::size_t list_builds() const { return detector_ ? detector_->builds() : 0; }
  double elastic_energy_J() const;
  // The contact list's detector (contact_detector.hpp: its fit, rebuild
  // check and checkpoint fields); null without detection.
  const ContactDetector* detector() const { return detector_.get(); }
  ContactDetector* detector() { return detector_.get(); }

  // Bonds, then unbonded contacts (numbered so, 0.. bonds.size() + contacts.size()).
  BondSet bonds, contacts;
  std::vector<int> bond_id;  // each bond's place in the tissue's list (reorder moves bonds)
  // Each contact's force on q (minus on p) and moments on its ends (moment[end],
  // end as in ContactIncidence's entries); one contact's in one cache line's
  // half, as a particle's sum reads them.
  struct Force {
    double fx, fy, moment[2];
  };
  std::vector<Force> force;
  ContactIncidence particle_contacts;  // each particle's contacts
  // Stable-step scratch: each contact's stiffness on its bodies (kr[2c + end]),
  // each body's contacts, and their sums per body.
  std::vector<double> contact_kt, contact_kr, body_kt, body_kr;
  ContactIncidence body_contacts;

 private:
  // One block of contacts' kinematics, in and out of the law (per thread).
  struct BlockScratch {
    alignas(64) double gap[kBlock], dn[kBlock], ds[kBlock], dth[kBlock], nx[kBlock], ny[kBlock];
    alignas(64) double lp[kBlock], lq[kBlock], fn[kBlock], fs[kBlock], mt[kBlock];
  };
  void permute_bonds(const std::vector<std::size_t>& perm);
  static void permute_set(BondSet& set, const std::vector<std::size_t>& perm);
  void set_constants(BondSet& set, std::size_t k, int p, int q, const DemBodies& bodies,
                     bool through_collagen = false) const;
  void block(const DemBodies& bodies, BondSet& set, std::size_t begin, std::size_t count, std::size_t number,
             double dt_s, BlockScratch& s);

  DemSpec spec_;
  std::unique_ptr<BoundContactLaw> law_;
  std::unique_ptr<ContactDetector> detector_;
  BondSet next_contacts_;  // rebuild_list's scratch
  std::vector<std::pair<int, int>> candidate_pairs_, candidate_scratch_;
};

}  // namespace fibrodem
