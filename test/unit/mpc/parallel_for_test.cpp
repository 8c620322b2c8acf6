// ParallelFor: every index exactly once per run, on the caller and the workers, whatever the
// run's size and however late a worker wakes; a run's body is never called after run() returns.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "mpc/parallel_for.hpp"

namespace ballast::test {
namespace {

TEST(ParallelFor, EveryIndexOnceInBackToBackRunsOfEverySize) {
  mpc::ParallelFor pool(3);
  ASSERT_EQ(pool.threads(), 3);
  std::vector<std::atomic<int>> hits(64);
  std::atomic<int> outside{0};
  for (int run = 0; run < 3000; ++run) {
    const int n = run % 65;  // 0 (nothing to do) .. 64
    for (auto& h : hits) h = 0;
    std::atomic<bool> running{true};
    auto body = [&](int i, int thread) {
      if (!running) ++outside;
      ASSERT_GE(thread, 0);
      ASSERT_LT(thread, pool.threads());
      ++hits[i];
    };
    pool.run(n, body);
    running = false;
    for (int i = 0; i < 64; ++i) ASSERT_EQ(hits[i].load(), i < n ? 1 : 0) << "run " << run;
  }
  // Late workers of earlier runs find them over: no body ran after its run returned.
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(outside.load(), 0);
}

TEST(ParallelFor, TheWorkersShareTheWork) {
  mpc::ParallelFor pool(2);
  std::atomic<int> byWorker{0};
  // Indices long enough that a worker woken within a few milliseconds gets some of them.
  auto body = [&](int, int thread) {
    std::this_thread::sleep_for(std::chrono::microseconds(500));
    if (thread == 1) ++byWorker;
  };
  pool.run(100, body);
  EXPECT_GT(byWorker.load(), 0);
}

}  // namespace
}  // namespace ballast::test
