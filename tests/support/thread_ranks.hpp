// Ranks as threads of one process, for the tests of what a run split over
// MPI ranks does (the coupling's solve, the DEM): messages and gathers
// through shared memory, each call a meeting of every rank, as the MPI
// calls are. With drop_halo, exchange() delivers nothing: the receivers
// keep whatever they held (a test that the halo matters).
#pragma once

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "util/rank_group.hpp"

namespace fibrodem::test {

class ThreadRanks {
 public:
  ThreadRanks(int size, bool drop_halo)
      : size_(size), drop_halo_(drop_halo), gathered_(static_cast<std::size_t>(size)) {}

  class Group final : public RankGroup {
   public:
    Group(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return all_.size_; }
    void exchange(const std::vector<HaloMessage>& messages) override {
      for (const HaloMessage& m : messages) {
        std::lock_guard<std::mutex> lock(all_.mutex_);
        all_.posted_[{rank_, m.rank}].assign(m.send, m.send + m.send_count);
      }
      all_.meet();
      if (!all_.drop_halo_)
        for (const HaloMessage& m : messages) {
          std::lock_guard<std::mutex> lock(all_.mutex_);
          const std::vector<double>& sent = all_.posted_.at({m.rank, rank_});
          if (sent.size() != m.receive_count) all_.layouts_agree = false;
          std::copy_n(sent.begin(), std::min(sent.size(), m.receive_count), m.receive);
        }
      all_.meet();
    }
    void gather_all(const double* mine, std::size_t count, double* every_rank) override {
      post(mine, count);
      for (int r = 0; r < all_.size_; ++r) copy_from(r, count, every_rank + r * static_cast<long>(count));
      all_.meet();
    }
    void gather_all_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                         const int* offsets) override {
      post(mine, count);
      for (int r = 0; r < all_.size_; ++r) copy_from(r, static_cast<std::size_t>(counts[r]), every_rank + offsets[r]);
      all_.meet();
    }
    void gather_into(const double* mine, std::size_t count, double* every_rank, const int* counts,
                     const int* offsets) override {
      post(mine, count);
      if (rank_ == 0)
        for (int r = 0; r < all_.size_; ++r) copy_from(r, static_cast<std::size_t>(counts[r]), every_rank + offsets[r]);
      all_.meet();
    }
    std::vector<std::vector<double>> gather(const std::vector<double>& mine) override {
      post(mine.data(), mine.size());
      std::vector<std::vector<double>> all;
      if (rank_ == 0) all = all_.gathered_;
      all_.meet();
      return all;
    }
    std::vector<std::string> gather_text(const std::string&) override { throw std::logic_error("not used"); }

   private:
    // This rank's values posted, then every rank's are there to read.
    void post(const double* mine, std::size_t count) {
      all_.gathered_[static_cast<std::size_t>(rank_)].assign(mine, mine + count);
      all_.meet();
    }
    void copy_from(int r, std::size_t count, double* to) {
      const std::vector<double>& from = all_.gathered_[static_cast<std::size_t>(r)];
      if (from.size() != count) all_.layouts_agree = false;
      std::copy_n(from.begin(), std::min(count, from.size()), to);
    }
    ThreadRanks& all_;
    int rank_;
  };
  bool layouts_agree = true;  // each message and gather as long as its receiver expects

  // each(group) on every rank's thread at once.
  template <class Each>
  void run(Each&& each) {
    std::vector<std::thread> threads;
    for (int r = 0; r < size_; ++r)
      threads.emplace_back([&, r] {
        Group group(*this, r);
        each(group);
      });
    for (auto& thread : threads) thread.join();
  }

 private:
  // Returns once every rank has called it.
  void meet() {
    std::unique_lock<std::mutex> lock(mutex_);
    const long generation = generation_;
    if (++arrived_ == size_) {
      arrived_ = 0;
      ++generation_;
      met_.notify_all();
    } else {
      met_.wait(lock, [&] { return generation_ != generation; });
    }
  }

  int size_;
  bool drop_halo_;
  std::mutex mutex_;
  std::condition_variable met_;
  int arrived_ = 0;
  long generation_ = 0;
  std::map<std::pair<int, int>, std::vector<double>> posted_;  // (from, to) -> values
  std::vector<std::vector<double>> gathered_;
};

}  // namespace fibrodem::test
