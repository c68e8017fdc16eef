// The writer thread of pictures and snapshots: jobs in order, failures
// thrown to the run, and run_here (used when no core is free for the writer)
// keeping both.
#include <doctest/doctest.h>

#include <stdexcept>
#include <thread>
#include <vector>

#include "io/background_writer.hpp"

using namespace fibrodem;

TEST_CASE("the background writer runs jobs in order, run_here after every job posted before it") {
  BackgroundWriter writer(2);
  std::vector<int> order;  // (written by one thread at a time: run_here waits for the posted jobs)
  std::thread::id ran_on;
  for (int k = 0; k < 5; ++k) writer.post([&order, k] { order.push_back(k); });
  writer.run_here([&] {
    order.push_back(5);
    ran_on = std::this_thread::get_id();
  });
  writer.post([&order] { order.push_back(6); });
  writer.finish();
  CHECK(order == std::vector<int>{0, 1, 2, 3, 4, 5, 6});
  CHECK(ran_on == std::this_thread::get_id());
}

TEST_CASE("a failed background job is thrown by the next run_here, and a job run here throws its own error") {
  BackgroundWriter writer(2);
  writer.post([] { throw std::runtime_error("cannot write snapshot_1.png"); });
  bool ran = false;
  CHECK_THROWS_WITH(writer.run_here([&] { ran = true; }), "cannot write snapshot_1.png");
  CHECK_FALSE(ran);
  CHECK_THROWS_WITH(writer.run_here([] { throw std::runtime_error("cannot write snapshot_2.png"); }),
                    "cannot write snapshot_2.png");
  writer.finish();  // nothing left to throw
}
