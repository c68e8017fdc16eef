#include "model/thread_governor.hpp"

#include <omp.h>

#include <algorithm>

namespace fibrodem {

void ThreadGovernor::use(int threads) {
  max_threads_ = current_ = std::max(1, threads);
  adapting_ = false;
  omp_set_num_threads(this->threads());
}

void ThreadGovernor::adapt(int max_threads) {
  max_threads_ = max_threads;
  adapting_ = max_threads > 1;
  current_ = max_threads;
  stretch_ = kFirstStretch;
  calls_ = {0, 0};
  switches_ = 0;
  begin_phase(false);
  omp_set_num_threads(threads());
}

int ThreadGovernor::chosen() const {
  if (max_threads_ == 0) return omp_get_max_threads();
  return adapting_ && trial_ ? other() : current_;
}

int ThreadGovernor::threads() const {
  if (max_threads_ == 0) return omp_get_max_threads();
  return std::max(1, chosen() - lent_);
}

void ThreadGovernor::lend(int cores) {
  lent_ = std::max(0, cores);
  if (max_threads_ > 0) omp_set_num_threads(threads());
}

void ThreadGovernor::begin_phase(bool trial) {
  trial_ = trial;
  left_ = trial ? kTrial : stretch_;
  measured_ = 0;
  sum_s_ = 0;
}

void ThreadGovernor::record(int used, double wall_s) {
  ++calls_[used > 1 ? 1 : 0];
  if (!adapting_ || lent_ > 0) return;
  // The last kTrial / 2 calls of a phase are measured: after a change of
  // count, the first calls refill the caches of cores that swapped cells.
  if (left_ <= kTrial / 2) {
    sum_s_ += wall_s;
    ++measured_;
  }
  if (--left_ > 0) return;
  const double mean_s = sum_s_ / static_cast<double>(std::max(1L, measured_));
  if (!trial_) {
    current_mean_s_ = mean_s;
    begin_phase(true);
  } else if (mean_s < kMargin * current_mean_s_) {
    current_ = other();
    ++switches_;
    stretch_ = kFirstStretch;
    begin_phase(false);
  } else {
    stretch_ = std::min(2 * stretch_, kLongestStretch);
    begin_phase(false);
  }
  omp_set_num_threads(this->threads());
}

}  // namespace fibrodem
