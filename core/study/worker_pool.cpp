#include "study/worker_pool.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

namespace fibrodem {

void for_each_in_parallel(std::size_t n, unsigned jobs, const std::function<void(std::size_t)>& work,
                          const std::function<void(std::size_t)>& done) {
  if (jobs == 0) jobs = std::max(1u, std::thread::hardware_concurrency());
  std::atomic<std::size_t> next{0};
  std::mutex done_lock;
  std::vector<std::thread> workers;
  for (unsigned w = 0; w < std::min<std::size_t>(jobs, std::max<std::size_t>(1, n)); ++w)
    workers.emplace_back([&] {
      for (std::size_t i; (i = next++) < n;) {
        work(i);
        if (done) {
          std::lock_guard<std::mutex> lock(done_lock);
          done(i);
        }
      }
    });
  for (auto& t : workers) t.join();
}

}  // namespace fibrodem
