// The MuJoCo backend in real time (not lockstep), as the Simbody backend's
// (test/integration/simbody/realtime_test.cpp): absolute deadlines, periods skipped after a stall
// and simulated with the commands held, a slow simulation step that makes the world wait rather
// than the controller late, and the host delays the acceptance tests inject. Wall-clock tests:
// they run alone (RUN_SERIAL) at real-time priority where the system grants it.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "mujoco_backend.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace ballast::mujoco {
namespace {

using backend::Status;
using simbody::test::SimConfig;

/// As ballastd's control thread: SCHED_FIFO where permitted (otherwise normal priority).
class MujocoRealTime : public ::testing::Test {
 protected:
  void SetUp() override {
    sched_param param{};
    param.sched_priority = 80;
    pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  }
  void TearDown() override {
    sched_param param{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
  }
};

TEST_F(MujocoRealTime, TheScheduleKeepsAbsoluteDeadlinesAndSkipsPeriodsAfterAStall) {
  SimConfig config;
  config.lockstep = false;
  config.period = 0.002;
  MujocoBackend sim;
  backend::Error error;
  ASSERT_TRUE(sim.configure(config.config(), error) && sim.start(error)) << error.message;
  const auto t0 = std::chrono::steady_clock::now();
  backend::TickTiming timing;
  for (int k = 0; k < 25; ++k) ASSERT_EQ(sim.advance(timing), Status::kOk);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(50));  // 25 x 2 ms
  // A stall of 20 ms (10 periods) in the tick's own work: the next advance() reports the tick
  // late, by at least the stall, and skips the periods gone instead of bursting through them.
  const std::uint64_t lateBefore = sim.lateTicks();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(sim.advance(timing), Status::kOk);
  EXPECT_TRUE(timing.late);
  EXPECT_GE(timing.lateness, 0.018);
  EXPECT_GE(timing.skipped, 9u);
  EXPECT_EQ(sim.lateTicks(), lateBefore + 1);
  // The world went on meanwhile: the next step simulates the skipped periods with the motors
  // holding their command, so simulated time keeps up with the wall.
  const std::uint32_t skipped = timing.skipped;
  backend::Sensors before, after;
  ASSERT_EQ(sim.read(before), Status::kOk);
  ASSERT_EQ(sim.advance(timing), Status::kOk);
  ASSERT_EQ(sim.read(after), Status::kOk);
  EXPECT_NEAR(after.time - before.time, (skipped + 1) * config.period, 1e-9);
}

TEST_F(MujocoRealTime, ASlowSimulationStepMakesTheWorldWaitNotTheControllerLate) {
  // 10 MuJoCo steps per 0.1 ms period take two to three periods (about 25 µs a step): the
  // world waits for the simulator instead, so the ticks are not late and no period is skipped;
  // simulated time falls behind the wall clock. (Not slower: with 40 steps the loop slept under
  // 5 % of the time at SCHED_FIFO and, once in 30 runs, stalled 42 ms, which is what the
  // kernel's real-time throttling, sched_rt_runtime_us 950000 of 1000000, does.)
  SimConfig config;
  config.lockstep = false;
  config.period = 1e-4;
  config.yaml = "substeps: 10\n";
  MujocoBackend sim;
  backend::Error error;
  ASSERT_TRUE(sim.configure(config.config(), error) && sim.start(error)) << error.message;
  backend::TickTiming timing;
  int late = 0, skipped = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 250; ++k) {
    ASSERT_EQ(sim.advance(timing), Status::kOk);
    late += timing.late;
    skipped += static_cast<int>(timing.skipped);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  backend::Sensors s;
  ASSERT_EQ(sim.read(s), Status::kOk);
  // Without the pause every tick would be late. Some are, on a host that preempts the loop at
  // this 0.1 ms period: Simbody 17 of 250 once in CI; here 1-5 (Simbody), 1-22 (MuJoCo) in 5
  // runs each. Half is far from either.
  std::printf("late %d, skipped %d of 250 ticks; simulated %.4f s in %.4f s\n", late, skipped,
              s.time, wall);
  EXPECT_LT(late, 250 / 2);
  EXPECT_LT(skipped, 250 / 2);
  EXPECT_NEAR(s.time, (250 + skipped) * config.period, 1e-9);
  EXPECT_GT(wall, 1.2 * s.time);  // the world fell behind the wall clock
}

TEST_F(MujocoRealTime, HostDelaysStallOnceAndJitterAFractionOfTicks) {
  SimConfig config;
  config.lockstep = false;
  config.period = 0.002;
  config.yaml = "host:\n  stall_at: 0.05\n  stall: 0.012\n  jitter_from: 0.1\n"
                "  jitter_fraction: 0.1\n  jitter: 0.004\n";
  MujocoBackend sim;
  backend::Error error;
  ASSERT_TRUE(sim.configure(config.config(), error) && sim.start(error)) << error.message;
  backend::TickTiming timing;
  int late = 0, lateAfterJitterStarts = 0;
  double worst = 0.0;
  for (int k = 0; k < 250; ++k) {
    ASSERT_EQ(sim.advance(timing), Status::kOk);
    if (!timing.late) continue;
    ++late;
    worst = std::max(worst, timing.lateness);
    backend::Sensors s;
    sim.read(s);
    if (s.time > 0.1) ++lateAfterJitterStarts;
  }
  // As for the simbody backend: one tick at least 10 ms late, about 10 % of the 200 ticks after
  // 0.1 s late (binomial 20 ± 4.2; the bounds are 3 σ).
  EXPECT_GE(worst, 0.010);
  EXPECT_GE(lateAfterJitterStarts, 7);
  EXPECT_LE(lateAfterJitterStarts, 45);
  EXPECT_GE(late, lateAfterJitterStarts + 1);
}

}  // namespace
}  // namespace ballast::mujoco
