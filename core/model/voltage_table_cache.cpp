#include "model/voltage_table_cache.hpp"

#include <cstring>

#include "model/population.hpp"
#include "model/voltage_table.hpp"

namespace fibrodem {

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// (a, b rows shared by an entry and its Rush-Larsen entry count in both: the
// budget errs on the small side.)
std::size_t bytes_of(const VoltageTableRows& r) {
  return sizeof r + ((r.rows ? r.rows->size() : 0) + r.rl_rows.size() + r.key.params.size() + r.key.initial_state.size()) *
                        sizeof(double) +
         r.gates.size() * sizeof(int);
}

}  // namespace

VoltageTableKey VoltageTableKey::of(const Population& pop, double v_min_mV, double v_max_mV, double step_mV) {
  VoltageTableKey key;
  key.model_name = pop.info().name;
  key.model_version = pop.info().version;
  key.model_origin = pop.model_origin;
  if (key.model_origin.empty()) key.model_kept = pop.model;
  key.cell_type = static_cast<int>(pop.type);
  key.voltage_state = pop.voltage_state;
  key.scalar_reference = pop.scalar_reference;
  key.params = pop.params;
  key.initial_state = pop.initial_state;
  key.v_min_mV = v_min_mV;
  key.v_max_mV = v_max_mV;
  key.step_mV = step_mV;
  return key;
}

bool VoltageTableKey::same_as(const VoltageTableKey& o) const {
  return model_name == o.model_name && model_version == o.model_version && model_origin == o.model_origin &&
         model_kept.get() == o.model_kept.get() && cell_type == o.cell_type && voltage_state == o.voltage_state &&
         scalar_reference == o.scalar_reference && same_bits(v_min_mV, o.v_min_mV) &&
         same_bits(v_max_mV, o.v_max_mV) && same_bits(step_mV, o.step_mV) &&
         same_bits(rush_larsen_dt_ms, o.rush_larsen_dt_ms) && same_bits(params, o.params) &&
         same_bits(initial_state, o.initial_state);
}

// Never destroyed: the process ends with it, and its rows (1.4 MB for the
// colman tables) are then returned whole with the address space, where a
// destructor at exit unmapped them one table at a time (a tenth of a
// millisecond of a one-cell run's CPU time).
VoltageTableCache& VoltageTableCache::instance() {
  static VoltageTableCache& cache = *new VoltageTableCache;
  return cache;
}

std::shared_ptr<const VoltageTableRows> VoltageTableCache::find(const VoltageTableKey& key) {
  std::lock_guard lock(mutex_);
  for (auto it = lru_.begin(); it != lru_.end(); ++it)
    if ((*it)->key.same_as(key)) {
      lru_.splice(lru_.begin(), lru_, it);
      ++hits_;
      return lru_.front();
    }
  ++misses_;
  return nullptr;
}

std::shared_ptr<const VoltageTableRows> VoltageTableCache::insert(std::shared_ptr<const VoltageTableRows> rows) {
  const std::size_t size = bytes_of(*rows);
  if (size > kBudgetBytes) return rows;
  std::lock_guard lock(mutex_);
  for (auto it = lru_.begin(); it != lru_.end(); ++it)
    if ((*it)->key.same_as(rows->key)) {  // built meanwhile by another thread: one copy is kept
      lru_.splice(lru_.begin(), lru_, it);
      return lru_.front();
    }
  while (!lru_.empty() && bytes_ + size > kBudgetBytes) {
    bytes_ -= bytes_of(*lru_.back());
    lru_.pop_back();  // tables in use by a run stay alive through its shared_ptr
  }
  lru_.push_front(rows);
  bytes_ += size;
  return rows;
}

void VoltageTableCache::clear() {
  std::lock_guard lock(mutex_);
  lru_.clear();
  bytes_ = 0;
  hits_ = misses_ = 0;
}

std::size_t VoltageTableCache::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}
std::size_t VoltageTableCache::entries() const {
  std::lock_guard lock(mutex_);
  return lru_.size();
}
long long VoltageTableCache::hits() const {
  std::lock_guard lock(mutex_);
  return hits_;
}
long long VoltageTableCache::misses() const {
  std::lock_guard lock(mutex_);
  return misses_;
}

}  // namespace fibrodem
