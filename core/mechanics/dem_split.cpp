#include "mechanics/dem_split.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "mechanics/dem_step_inline.hpp"

namespace fibrodem {

namespace {

// A collagen disk's rank: that of the first body with a rank its bonds reach
// (chains of collagen followed), else rank 0.
void give_collagen_ranks(std::vector<int>& body_rank, const DemBodies& bodies, const BondSet& bonds) {
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k < bonds.size(); ++k) {
      const int bp = bodies.pbody[bonds.p[k]], bq = bodies.pbody[bonds.q[k]];
      for (auto [to, from] : {std::pair{bp, bq}, std::pair{bq, bp}})
        if (body_rank[to] < 0 && body_rank[from] >= 0) {
          body_rank[to] = body_rank[from];
          changed = true;
        }
    }
  }
  std::replace(body_rank.begin(), body_rank.end(), -1, 0);
}

}  // namespace

DemSplit::DemSplit(RankGroup& ranks, const std::vector<int>& cell_rank, DemBodies& bodies, const DemContacts& contacts)
    : ranks_(ranks), body_rank_(bodies.size(), -1) {
  if (cell_rank.size() != bodies.cells)
    throw std::invalid_argument("DEM over ranks: " + std::to_string(cell_rank.size()) + " cells' ranks for " +
                                std::to_string(bodies.cells) + " cells");
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies.bcell[b] >= 0) body_rank_[b] = cell_rank[static_cast<std::size_t>(bodies.bcell[b])];
  give_collagen_ranks(body_rank_, bodies, contacts.bonds);
  const int size = ranks_.size(), me = ranks_.rank();
  bodies.own.assign(bodies.size(), 0);
  body_counts_.assign(size, 0);
  particle_counts_.assign(size, 0);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int r = body_rank_[b];
    body_counts_[r] += static_cast<int>(kEvolvingBodyArrays);
    particle_counts_[r] += 2 * (bodies.body_particle_start[b + 1] - bodies.body_particle_start[b]);
    if (r != me) continue;
    bodies.own[b] = 1;
    own_bodies_.push_back(static_cast<int>(b));
  }
  bodies_in_rank_order_.resize(bodies.size());
  std::iota(bodies_in_rank_order_.begin(), bodies_in_rank_order_.end(), 0);
  std::stable_sort(bodies_in_rank_order_.begin(), bodies_in_rank_order_.end(),
                   [&](int a, int b) { return body_rank_[a] < body_rank_[b]; });
  body_offsets_.assign(size, 0);
  particle_offsets_.assign(size, 0);
  for (int r = 1; r < size; ++r) {
    body_offsets_[r] = body_offsets_[r - 1] + body_counts_[r - 1];
    particle_offsets_[r] = particle_offsets_[r - 1] + particle_counts_[r - 1];
  }
  // This rank's particles as runs of indices (a body's particles ascend,
  // and bodies follow their first particles).
  for (std::size_t i = 0; i < bodies.particle_count(); ++i) {
    if (!bodies.own[static_cast<std::size_t>(bodies.pbody[i])]) continue;
    if (!own_particle_runs_.empty() && own_particle_runs_.back().second == static_cast<int>(i))
      ++own_particle_runs_.back().second;
    else
      own_particle_runs_.emplace_back(static_cast<int>(i), static_cast<int>(i) + 1);
  }
  bodies.partition_bodies();
}

// Each contact between this rank's body and another rank's puts the one in
// the other's halo; both ranks list the pair, so their lists agree.
void DemSplit::plan_halo(const DemBodies& bodies, const DemContacts& contacts) {
  count_own(contacts, bodies);
  const int me = ranks_.rank();
  std::vector<std::vector<int>> send(ranks_.size()), receive(ranks_.size());
  auto add = [&](const BondSet& set, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) {
      const int bp = bodies.pbody[set.p[k]], bq = bodies.pbody[set.q[k]];
      const int rp = body_rank_[bp], rq = body_rank_[bq];
      if (rp == rq) continue;
      const bool p_mine = rp == me;
      send[p_mine ? rq : rp].push_back(p_mine ? bp : bq);
      receive[p_mine ? rq : rp].push_back(p_mine ? bq : bp);
    }
  };
  add(contacts.bonds, own_bonds_);
  add(contacts.contacts, own_contacts_);
  neighbours_.clear();
  for (int r = 0; r < ranks_.size(); ++r) {
    for (auto* list : {&send[r], &receive[r]}) {
      std::sort(list->begin(), list->end());
      list->erase(std::unique(list->begin(), list->end()), list->end());
    }
    if (!send[r].empty() || !receive[r].empty()) neighbours_.push_back({r, std::move(send[r]), std::move(receive[r])});
  }
  send_.resize(neighbours_.size());
  receive_.resize(neighbours_.size());
  messages_.resize(neighbours_.size());
  for (std::size_t k = 0; k < neighbours_.size(); ++k) {
    send_[k].resize(neighbours_[k].send.size() * kEvolvingBodyArrays);
    receive_[k].resize(neighbours_[k].receive.size() * kEvolvingBodyArrays);
    messages_[k] = {neighbours_[k].rank, send_[k].data(), send_[k].size(), receive_[k].data(), receive_[k].size()};
  }
}

// The contacts this rank computes: those that touch its bodies, first in
// each set (the split's order).
void DemSplit::count_own(const DemContacts& contacts, const DemBodies& bodies) {
  const ContactOrder own = order(bodies);
  auto count = [&](const BondSet& set) {
    std::size_t n = 0;
    while (n < set.size() && own.fast(set.p[n], set.q[n])) ++n;
    for (std::size_t k = n; k < set.size(); ++k)
      if (own.fast(set.p[k], set.q[k])) throw std::logic_error("DEM over ranks: contacts not in the split's order");
    return n;
  };
  own_bonds_ = count(contacts.bonds);
  own_contacts_ = count(contacts.contacts);
}

void DemSplit::pack(const DemBodies& bodies, const std::vector<int>& list, double* out) const {
  std::size_t a = 0;
  for_each_evolving_body_array(bodies, [&](const char*, const std::vector<double>& v) {
    for (std::size_t k = 0; k < list.size(); ++k)
      out[k * kEvolvingBodyArrays + a] = v[static_cast<std::size_t>(list[k])];
    ++a;
  });
}

// Other ranks' bodies' state, and their particles placed as their owners
// placed them (this rank's own bodies in `list` are passed over).
void DemSplit::unpack(DemBodies& bodies, const std::vector<int>& list, const double* in) const {
  std::size_t a = 0;
  for_each_evolving_body_array(bodies, [&](const char*, std::vector<double>& v) {
    for (std::size_t k = 0; k < list.size(); ++k) {
      const auto b = static_cast<std::size_t>(list[k]);
      if (!bodies.own[b]) v[b] = in[k * kEvolvingBodyArrays + a];
    }
    ++a;
  });
  for (int b : list)
    if (!bodies.own[static_cast<std::size_t>(b)]) bodies.place_particles_of(static_cast<std::size_t>(b));
}

void DemSplit::refresh_ghosts(DemBodies& bodies) {
  for (std::size_t k = 0; k < neighbours_.size(); ++k) pack(bodies, neighbours_[k].send, send_[k].data());
  ranks_.exchange(messages_);
  for (std::size_t k = 0; k < neighbours_.size(); ++k) unpack(bodies, neighbours_[k].receive, receive_[k].data());
}

void DemSplit::share_bodies(DemBodies& bodies) {
  mine_.resize(own_bodies_.size() * kEvolvingBodyArrays);
  every_.resize(bodies.size() * kEvolvingBodyArrays);
  pack(bodies, own_bodies_, mine_.data());
  ranks_.gather_all_into(mine_.data(), mine_.size(), every_.data(), body_counts_.data(), body_offsets_.data());
  unpack(bodies, bodies_in_rank_order_, every_.data());
}

void DemSplit::gather_bodies(DemBodies& bodies, bool old_places) {
  const bool root = ranks_.rank() == 0;
  mine_.resize(own_bodies_.size() * kEvolvingBodyArrays);
  if (root) every_.resize(bodies.size() * kEvolvingBodyArrays);
  pack(bodies, own_bodies_, mine_.data());
  ranks_.gather_into(mine_.data(), mine_.size(), every_.data(), body_counts_.data(), body_offsets_.data());
  if (root) unpack(bodies, bodies_in_rank_order_, every_.data());
  if (!old_places) return;
  mine_.clear();
  mine_.reserve(static_cast<std::size_t>(particle_counts_[static_cast<std::size_t>(ranks_.rank())]));
  for (int b : own_bodies_)
    for (int j = bodies.body_particle_start[b]; j < bodies.body_particle_start[b + 1]; ++j) {
      const auto i = static_cast<std::size_t>(bodies.body_particle[j]);
      mine_.push_back(bodies.px_old[i]);
      mine_.push_back(bodies.py_old[i]);
    }
  if (root) every_.resize(2 * bodies.particle_count());
  ranks_.gather_into(mine_.data(), mine_.size(), every_.data(), particle_counts_.data(), particle_offsets_.data());
  if (root) {
    std::size_t k = 0;
    for (int b : bodies_in_rank_order_)
      for (int j = bodies.body_particle_start[b]; j < bodies.body_particle_start[b + 1]; ++j) {
        const auto i = static_cast<std::size_t>(bodies.body_particle[j]);
        bodies.px_old[i] = every_[k++];
        bodies.py_old[i] = every_[k++];
      }
  }
  release_buffers();
}

// The buffers of a checkpoint's (or the run end's) gathers, every particle's
// or contact's, are not kept for the rest of the run (35 MB on rank 0 of a
// 509,509-particle sheet); the bodies' (every list rebuild) grow them again.
void DemSplit::release_buffers() {
  std::vector<double>().swap(mine_);
  std::vector<double>().swap(every_);
}

// Each rank walks both sets in one process's order (the same on every
// rank) and sends, in that order, the state of the contacts whose particle
// p is its own, which rank 0 takes in the same order rank by rank.
void DemSplit::gather_contacts(DemContacts& contacts, const DemBodies& bodies) {
  const DemContacts::TissueOrder order = contacts.tissue_order();
  const std::pair<BondSet*, const std::vector<std::size_t>*> sets[] = {{&contacts.bonds, &order.bonds},
                                                                         {&contacts.contacts, &order.contacts}};
  constexpr int kFields = 4;  // fn, fs, mb, intact
  const int me = ranks_.rank(), size = ranks_.size();
  auto rank_of = [&](const BondSet& set, std::size_t k) { return body_rank_[bodies.pbody[set.p[k]]]; };
  std::vector<int> counts(size, 0), offsets(size, 0);
  for (const auto& [set, set_order] : sets)
    for (std::size_t k : *set_order) counts[rank_of(*set, k)] += kFields;
  mine_.clear();
  mine_.reserve(static_cast<std::size_t>(counts[me]));  // (grown by doubling it would take up to twice)
  for (const auto& [set, set_order] : sets)
    for (std::size_t k : *set_order)
      if (rank_of(*set, k) == me)
        mine_.insert(mine_.end(), {set->fn[k], set->fs[k], set->mb[k], static_cast<double>(set->intact[k])});
  for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  if (me == 0) every_.resize(static_cast<std::size_t>(offsets[size - 1] + counts[size - 1]));
  ranks_.gather_into(mine_.data(), mine_.size(), every_.data(), counts.data(), offsets.data());
  if (me != 0) return release_buffers();
  std::vector<int> next = offsets;
  for (const auto& [set, set_order] : sets)
    for (std::size_t k : *set_order) {
      int& at = next[rank_of(*set, k)];
      const double* v = every_.data() + at;
      at += kFields;
      set->fn[k] = v[0];
      set->fs[k] = v[1];
      set->mb[k] = v[2];
      set->intact[k] = static_cast<std::uint8_t>(v[3]);
    }
  release_buffers();
}

void DemSplit::sum(double* values, std::size_t count) {
  reduce_.resize(count * static_cast<std::size_t>(ranks_.size()));
  ranks_.gather_all(values, count, reduce_.data());
  for (std::size_t j = 0; j < count; ++j) {
    double total = 0;
    for (int r = 0; r < ranks_.size(); ++r) total += reduce_[static_cast<std::size_t>(r) * count + j];
    values[j] = total;
  }
}

void DemSplit::max(double* values, std::size_t count) {
  reduce_.resize(count * static_cast<std::size_t>(ranks_.size()));
  ranks_.gather_all(values, count, reduce_.data());
  for (std::size_t j = 0; j < count; ++j)
    for (int r = 0; r < ranks_.size(); ++r)
      values[j] = std::max(values[j], reduce_[static_cast<std::size_t>(r) * count + j]);
}

ContactDetector::Departure DemSplit::departure(const ContactDetector& detector, const ContactDetector::AffineFit& fit,
                                               const DemBodies& bodies) {
  ContactDetector::Departure d;
  for (const auto& [begin, end] : own_particle_runs_) {
    const ContactDetector::Departure run =
        detector.departure(fit, bodies.px.data(), bodies.py.data(), bodies.pr.data(), static_cast<std::size_t>(begin),
                           static_cast<std::size_t>(end));
    d = {std::max(d.u2, run.u2), std::max(d.dr, run.dr), std::max(d.not_finite, run.not_finite)};
  }
  double values[3] = {d.u2, d.dr, d.not_finite};
  max(values, 3);
  return {values[0], values[1], values[2]};
}

}  // namespace fibrodem
