// The writer thread of pictures and snapshots: jobs in order, failures
// thrown to the run, and idle() (a run that lent the writer a core takes it
// back once the writer is idle) true only once every job is done.
#include <doctest/doctest.h>

#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "io/background_writer.hpp"

using namespace fibrodem;

TEST_CASE("the background writer runs jobs in order on its own thread, and is idle only once all are done" * doctest::test_suite("threads")) {
  BackgroundWriter writer(8);
  CHECK(writer.idle());
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::vector<int> order;  // (written by the writer's thread only, read after finish())
  std::thread::id ran_on;
  writer.post([&, released] {
    released.wait();
    ran_on = std::this_thread::get_id();
    order.push_back(0);
  });
  for (int k = 1; k < 5; ++k) writer.post([&order, k] { order.push_back(k); });
  CHECK_FALSE(writer.idle());  // the first job waits for `release`, four more behind it
  release.set_value();
  writer.finish();
  CHECK(writer.idle());
  CHECK(order == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(ran_on != std::this_thread::get_id());
}

TEST_CASE("a failed background job is thrown once, by the next finish(), and leaves the writer idle") {
  BackgroundWriter writer(2);
  writer.post([] { throw std::runtime_error("cannot write snapshot_1.png"); });
  CHECK_THROWS_WITH(writer.finish(), "cannot write snapshot_1.png");
  CHECK(writer.idle());
  CHECK_NOTHROW(writer.finish());  // nothing left to throw
  bool ran = false;
  writer.post([&] { ran = true; });
  writer.finish();
  CHECK(ran);
}
