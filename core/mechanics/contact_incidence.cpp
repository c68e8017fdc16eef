#include "mechanics/contact_incidence.hpp"

namespace fibrodem {

// Counting sort by owner; contacts visited in ascending number, so each
// owner's entries ascend.
void ContactIncidence::build(std::size_t owners, const BondSet& first, const BondSet& second,
                             const int* owner_of) {
  auto owner = [owner_of](int particle) { return owner_of ? owner_of[particle] : particle; };
  start_.assign(owners + 1, 0);
  for (const BondSet* set : {&first, &second})
    for (std::size_t k = 0; k < set->size(); ++k) {
      ++start_[owner(set->p[k]) + 1];
      ++start_[owner(set->q[k]) + 1];
    }
  for (std::size_t o = 0; o < owners; ++o) start_[o + 1] += start_[o];
  entry_.resize(static_cast<std::size_t>(start_[owners]));
  fill_.assign(start_.begin(), start_.end() - 1);
  int c = 0;
  for (const BondSet* set : {&first, &second})
    for (std::size_t k = 0; k < set->size(); ++k, ++c) {
      entry_[fill_[owner(set->p[k])]++] = 2 * c;
      entry_[fill_[owner(set->q[k])]++] = 2 * c + 1;
    }
}

}  // namespace fibrodem
