#include "gazedirector/util/thread_pool.h"

#include <atomic>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

// Every index runs exactly once, on a worker slot in range, and no two bodies
// share a slot at the same time (the fitter keeps a renderer per slot).
TEST(ThreadPoolTest, EveryIndexRunsOnceAndNoSlotIsSharedAtOnce) {
  ThreadPool pool(3);
  ASSERT_EQ(pool.size(), 3);
  for (int round = 0; round < 20; ++round) {
    const int count = 1 + 37 * round % 200;
    std::vector<std::atomic<int>> runs(count);
    std::vector<std::atomic<int>> in_slot(pool.size());
    std::atomic<bool> shared{false};
    pool.ParallelFor(count, [&](int index, int worker) {
      ASSERT_GE(worker, 0);
      ASSERT_LT(worker, pool.size());
      if (in_slot[worker].fetch_add(1) != 0) shared = true;
      ++runs[index];
      in_slot[worker].fetch_sub(1);
    });
    for (int i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << "round " << round << " index " << i;
    EXPECT_FALSE(shared);
  }
  pool.ParallelFor(0, [](int, int) { FAIL() << "no index to run"; });
}

// A failing body stops the loop and its exception reaches the caller; the
// pool stays usable.
TEST(ThreadPoolTest, AnExceptionReachesTheCallerAndThePoolGoesOn) {
  ThreadPool pool(2);
  EXPECT_THROW(pool.ParallelFor(100, [](int index, int) {
    if (index == 17) throw std::runtime_error("index 17");
  }),
               std::runtime_error);
  std::atomic<int> sum{0};
  pool.ParallelFor(10, [&](int index, int) { sum += index; });
  EXPECT_EQ(sum.load(), 45);
}

}  // namespace
}  // namespace gazedirector
