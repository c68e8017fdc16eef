// The DEM of a run split over ranks (docs/guide/parallel.md, "The DEM over
// ranks"). Every rank holds the whole tissue's bodies, particles and
// contacts, as it holds every cell's V, and steps its own share of them:
// the bodies of its own cells (a collagen disk, of no cell, goes with the
// cell body its first bond joins, else to rank 0) and the contacts that
// touch them, which the contact order puts first (ContactOrder with these
// bodies as its `light` ones). So the cell lengths that drive a body are
// its own rank's, and nothing of them travels.
//
// A step: each rank moves its own bodies; their state goes to the ranks
// whose bodies they touch (the halo: each contact between two ranks'
// bodies is computed on both, from the same values, so both have its
// force's bits); each rank places its ghosts' particles, computes its
// contacts' forces and kicks its bodies. A body's force is summed over its
// contacts in one process's order, so every body moves as in one process
// to rounding (a contact's force and a ghost's particles are computed in
// other SIMD lanes and loops than there, which may round otherwise). The
// sums over every body (the strain's fit, the contact list's affine fit)
// and the list's maxima are reduced over the ranks in rank order: the same
// bits for the same number of ranks. When the list must be
// rebuilt, every body's state goes to every rank, which then builds the
// whole tissue's list as one process does: the ranks agree on it without
// another message.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mechanics/contact_detector.hpp"
#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_contacts.hpp"
#include "util/rank_group.hpp"

namespace fibrodem {

class DemSplit {
 public:
  // `cell_rank`: each cell's rank (the run's partition). Marks the bodies
  // this rank steps in bodies.own (and parts them again).
  DemSplit(RankGroup& ranks, const std::vector<int>& cell_rank, DemBodies& bodies, const DemContacts& contacts);

  // The contacts in the split's order (own first) and their halo, after
  // they changed.
  ContactOrder order(const DemBodies& bodies) const { return {bodies.own.data(), bodies.pbody.data()}; }
  void plan_halo(const DemBodies& bodies, const DemContacts& contacts);
  std::size_t own_bonds() const { return own_bonds_; }
  std::size_t own_contacts() const { return own_contacts_; }

  // Ghost bodies' state from their owners, their particles placed.
  void refresh_ghosts(DemBodies& bodies);
  // Every body's state from its owner, its particles placed: on every rank
  // (before the whole tissue's contact list is built) or on rank 0 only
  // (pictures; with `old_places`, also the particles' places a step ago,
  // which a checkpoint holds).
  void share_bodies(DemBodies& bodies);
  void gather_bodies(DemBodies& bodies, bool old_places);
  // Rank 0: every contact's evolving state (force, moment, bond intact) from
  // the rank whose body its particle p is (the sets stay in their order).
  void gather_contacts(DemContacts& contacts, const DemBodies& bodies);

  // In place over the ranks: sums (every rank's added in rank order) and maxima.
  void sum(double* values, std::size_t count);
  void max(double* values, std::size_t count);
  // The contact list's check over this rank's particles, reduced.
  ContactDetector::Departure departure(const ContactDetector& detector, const ContactDetector::AffineFit& fit,
                                       const DemBodies& bodies);

  int rank() const { return ranks_.rank(); }
  const std::vector<int>& body_rank() const { return body_rank_; }

 private:
  void count_own(const DemContacts& contacts, const DemBodies& bodies);
  void pack(const DemBodies& bodies, const std::vector<int>& list, double* out) const;
  void unpack(DemBodies& bodies, const std::vector<int>& list, const double* in) const;

  RankGroup& ranks_;
  std::vector<int> body_rank_;                           // each body's rank
  std::vector<int> own_bodies_;                          // ascending
  std::vector<std::pair<int, int>> own_particle_runs_;   // [begin, end) of this rank's particles
  std::vector<int> bodies_in_rank_order_;                // rank after rank, each ascending
  std::vector<int> body_counts_, body_offsets_;          // x kEvolvingBodyArrays values
  std::vector<int> particle_counts_, particle_offsets_;  // x 2 values (places a step ago)
  std::size_t own_bonds_ = 0, own_contacts_ = 0;
  // The halo: per neighbouring rank, the bodies sent and received (ascending).
  struct Neighbour {
    int rank;
    std::vector<int> send, receive;
  };
  std::vector<Neighbour> neighbours_;
  std::vector<std::vector<double>> send_, receive_;
  std::vector<HaloMessage> messages_;
  std::vector<double> mine_, every_, reduce_;
  void release_buffers();
};

}  // namespace fibrodem
