// The Simbody backend in real time (not lockstep): absolute deadlines, periods skipped after a
// stall and simulated with the commands held, a slow simulation step that makes the world wait
// rather than the controller late, and the host delays the acceptance tests inject. Wall-clock
// tests: they run alone (RUN_SERIAL) at real-time priority where the system grants it.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "simbody_backend.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace ballast::simbody::test {
namespace {

using backend::Status;

/// As ballastd's control thread: SCHED_FIFO where permitted (otherwise normal priority).
class RealTime : public ::testing::Test {
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

TEST_F(RealTime, TheScheduleKeepsAbsoluteDeadlinesAndSkipsPeriodsAfterAStall) {
  SimConfig config;
  config.lockstep = false;
  config.period = 0.002;
  SimbodyBackend sim;
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

TEST_F(RealTime, ASlowSimulationStepMakesTheWorldWaitNotTheControllerLate) {
  // At 1e-8 accuracy the integrator takes about 0.5 ms per step, more than the 0.1 ms period:
  // the world waits for the simulator instead, so the ticks are not late and no period is
  // skipped; simulated time falls behind the wall clock.
  SimConfig config;
  config.lockstep = false;
  config.period = 1e-4;
  config.yaml = "integrator: rkm\naccuracy: 1.0e-8\n";
  SimbodyBackend sim;
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

/// A thread of higher SCHED_FIFO priority on the calling thread's CPU that, when released, takes
/// that CPU for a while: the host not running the control thread although it is ready, as a
/// kernel without PREEMPT_RT or a virtual machine's host does. Needs SCHED_FIFO (ok() says).
class CpuThief {
 public:
  CpuThief() {
    CPU_ZERO(&cpu_);
    CPU_SET(sched_getcpu(), &cpu_);
    pthread_getaffinity_np(pthread_self(), sizeof saved_, &saved_);
    ok_ = pthread_setaffinity_np(pthread_self(), sizeof cpu_, &cpu_) == 0;
    thread_ = std::thread([this] { run(); });
    sched_param param{};
    param.sched_priority = 90;
    ok_ = ok_ && pthread_setaffinity_np(thread_.native_handle(), sizeof cpu_, &cpu_) == 0 &&
          pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param) == 0;
  }
  ~CpuThief() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_one();
    thread_.join();
    pthread_setaffinity_np(pthread_self(), sizeof saved_, &saved_);
  }
  bool ok() const { return ok_; }
  /// Takes the CPU for `seconds` from `after` seconds from now (0: at once, preempting the
  /// caller within its work; later: while the caller sleeps, delaying its wake-up).
  void steal(double after, double seconds) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      after_ = after;
      seconds_ = seconds;
      due_ = true;
    }
    wake_.notify_one();
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return due_ || quit_; });
      if (quit_) return;
      due_ = false;
      const auto from = std::chrono::steady_clock::now() + std::chrono::duration<double>(after_);
      const auto until = from + std::chrono::duration<double>(seconds_);
      lock.unlock();
      std::this_thread::sleep_until(from);
      while (std::chrono::steady_clock::now() < until) {
      }
      lock.lock();
    }
  }

  cpu_set_t cpu_, saved_;
  bool ok_ = false;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool due_ = false, quit_ = false;
  double after_ = 0.0, seconds_ = 0.0;
};

/// A Simbody backend in real time at 2 ms periods with `yaml` as its section, started.
struct RealTimeSim {
  explicit RealTimeSim(const std::string& yaml = "") {
    config.lockstep = false;
    config.period = 0.002;
    config.yaml = yaml;
  }
  ::testing::AssertionResult start() {
    backend::Error error;
    if (sim.configure(config.config(), error) && sim.start(error))
      return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << error.message;
  }
  SimConfig config;
  SimbodyBackend sim;
};

TEST_F(RealTime, TheWorldWaitsForAHostThatDoesNotRunTheControlThread) {
  // The simulator runs on the host: when the host does not run the control thread although it
  // is ready, the world stops with it (one period simulated, no period skipped, not late) and
  // the tick says how long (host_stall); the controller's own stalls (it blocks: the test
  // above) still pass in the world.
  RealTimeSim rt;
  ASSERT_TRUE(rt.start());
  SimbodyBackend& sim = rt.sim;
  const SimConfig& config = rt.config;
  CpuThief thief;
  if (!thief.ok()) GTEST_SKIP() << "needs SCHED_FIFO and CPU affinity to emulate the host";
  backend::TickTiming timing;
  for (int k = 0; k < 25; ++k) ASSERT_EQ(sim.advance(timing), Status::kOk);
  backend::Sensors before, after_stall;
  ASSERT_EQ(sim.read(before), Status::kOk);
  for (const double after : {0.0, 0.001}) {  // preempted in the tick's work; a late wake-up
    SCOPED_TRACE(after == 0.0 ? "preempted in its work" : "woken late");
    thief.steal(after, 0.020);
    ASSERT_EQ(sim.advance(timing), Status::kOk);
    double waited = timing.host_stall;
    // A wake-up can come late in this advance() or, when the thief began before this tick's
    // pacing slept, show as preemption in the next one.
    ASSERT_EQ(sim.advance(timing), Status::kOk);
    waited += timing.host_stall;
    ASSERT_EQ(sim.read(after_stall), Status::kOk);
    EXPECT_GE(waited, 0.015);
    EXPECT_NEAR(after_stall.time - before.time, 2 * config.period, 1e-9);  // nothing skipped
    before = after_stall;
  }
}

TEST_F(RealTime, AnInjectedDelayIsTheControllersAndItsLateWakeUpTheHosts) {
  // A 10 ms delay injected into the tick (as a slow tick's work) passes in the world: the tick
  // is late by it. The host keeping the thread asleep past the delay's end (the thief runs from
  // 3 to 18 ms) is the host's: the world waits for that part, and the tick says so.
  RealTimeSim rt("host:\n  stall_at: 0.05\n  stall: 0.010\n");
  ASSERT_TRUE(rt.start());
  SimbodyBackend& sim = rt.sim;
  const SimConfig& config = rt.config;
  CpuThief thief;
  if (!thief.ok()) GTEST_SKIP() << "needs SCHED_FIFO and CPU affinity to emulate the host";
  backend::TickTiming timing;
  backend::Sensors s;
  for (;;) {
    ASSERT_EQ(sim.advance(timing), Status::kOk);
    ASSERT_EQ(sim.read(s), Status::kOk);
    if (s.time + config.period >= 0.05 - 1e-9) break;  // the next tick's delay is due
  }
  thief.steal(0.003, 0.015);
  ASSERT_EQ(sim.advance(timing), Status::kOk);
  EXPECT_TRUE(timing.late);
  EXPECT_GE(timing.lateness, 0.010 - config.period);   // the delay asked for is the tick's
  EXPECT_LT(timing.lateness, 0.0125);                  // the late wake-up (~7 ms) is not
  EXPECT_GE(timing.host_stall, 0.005);
}

TEST_F(RealTime, HostDelaysStallOnceAndJitterAFractionOfTicks) {
  SimConfig config;
  config.lockstep = false;
  config.period = 0.002;
  config.yaml = "host:\n  stall_at: 0.05\n  stall: 0.012\n  jitter_from: 0.1\n"
                   "  jitter_fraction: 0.1\n  jitter: 0.004\n";
  SimbodyBackend sim;
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
  // The stall: one tick at least 10 ms late. The jitter: about 10 % of the 200 ticks after
  // 0.1 s are 2 ms late (binomial: 20 ± 4.2; the bounds are 3 σ).
  EXPECT_GE(worst, 0.010);
  EXPECT_GE(lateAfterJitterStarts, 7);
  EXPECT_LE(lateAfterJitterStarts, 45);
  EXPECT_GE(late, lateAfterJitterStarts + 1);
}

}  // namespace
}  // namespace ballast::simbody::test
