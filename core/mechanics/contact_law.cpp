#include "mechanics/contact_law.hpp"

#include <stdexcept>

namespace fibrodem {

void BondSet::resize(std::size_t n) {
  p.resize(n);
  q.resize(n);
  kn.resize(n);
  ks.resize(n);
  m_eff.resize(n);
  ref_gap.resize(n);
  cn.resize(n);
  cs.resize(n);
  kb.resize(n);
  fn.resize(n);
  fs.resize(n);
  mb.resize(n);
  intact.resize(n);
}

const std::map<std::string, ContactLawFactory>& contact_laws() {
  static const std::map<std::string, ContactLawFactory> laws = {
      {"linear_bond", make_linear_bond_law},
      {"linear_parallel_bond", make_linear_parallel_bond_law},
  };
  return laws;
}

std::unique_ptr<ContactLaw> make_contact_law(const DemSpec& spec) {
  const auto it = contact_laws().find(spec.contact_law);
  if (it == contact_laws().end())
    throw std::invalid_argument("unknown contact law '" + spec.contact_law + "'");
  return it->second(spec);
}

}  // namespace fibrodem
