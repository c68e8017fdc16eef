// Which contacts act on each particle (or each body), in a fixed order: the
// DEM solver computes every contact's force in parallel into per-contact
// arrays, then sums them per particle along these lists. No atomics, no sum
// whose order depends on the threads: the result is the same for any number
// of threads, and the same as a serial loop over the contacts that adds each
// force to both ends as it goes.
//
// Contacts are numbered across the solver's sets in order (bonds 0 .. nb-1,
// then the unbonded contacts nb ...). An entry 2c + end names contact c and the
// end of it the owner holds (1: q, 0: p); each owner's entries ascend in c.
#pragma once

#include <cstddef>
#include <vector>

#include "mechanics/contact_law.hpp"

namespace fibrodem {

class ContactIncidence {
 public:
  // The lists of `owners` owners over the contacts of `first` then `second`;
  // owner_of[i] is particle i's owner (nullptr: the particle itself).
  void build(std::size_t owners, const BondSet& first, const BondSet& second, const int* owner_of = nullptr);

  const int* begin(std::size_t owner) const { return entry_.data() + start_[owner]; }
  const int* end(std::size_t owner) const { return entry_.data() + start_[owner + 1]; }

  static int contact(int entry) { return entry >> 1; }
  static bool is_q(int entry) { return (entry & 1) != 0; }

 private:
  std::vector<int> start_, fill_, entry_;  // CSR, kept between builds (no allocation once sized)
};

}  // namespace fibrodem
