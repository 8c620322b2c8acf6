// The real-time deadline policy (issue 12): a late tick is counted and shown, never a fault by
// itself; the faults are the motors going without commands for longer than
// safety.max_command_gap and more than safety.max_late_fraction of the last second's ticks
// late. An exception in the control or planner thread is a fault, the motors are damped and the
// daemon goes on. The loop runs in real-time mode on the fake backend with a scripted schedule
// and clocks the test advances itself (the wall clock, and the backend's through skipped
// periods), so every case is exact.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <random>
#include <stdexcept>
#include <vector>

#include "control/control_loop.hpp"
#include "test/unit/control/attached_planner.hpp"
#include "profile/settings.hpp"
#include "test/unit/test_support.hpp"

extern "C" const ballast::backend::BackendEntry* ballast_backend_entry();

namespace ballast::control {
namespace {

std::uint64_t g_clock = 1;  // ns; advanced by ScriptedBackend::advance
std::uint64_t fakeClock() { return g_clock; }

/// The fake backend with a scripted schedule: each advance() moves the wall clock on by one
/// period plus the tick's lateness and reports the TickTiming a pacer would.
class ScriptedBackend final : public backend::Backend {
 public:
  explicit ScriptedBackend(backend::Backend& inner) : inner_(inner) {}
  bool configure(const backend::Config& c, backend::Error& e) override {
    return inner_.configure(c, e);
  }
  const backend::Capabilities& capabilities() const override { return inner_.capabilities(); }
  bool start(backend::Error& e) override { return inner_.start(e); }
  backend::Status read(backend::Sensors& s) override {
    if (throw_on_read) {
      throw_on_read = false;
      throw std::runtime_error("injected: the bus driver threw");
    }
    const backend::Status status = inner_.read(s);
    s.time += skipped_time_;  // the backend's clock went on through the skipped periods
    return status;
  }
  backend::Status write(const backend::Commands& c) override { return inner_.write(c); }
  backend::Status advance(backend::TickTiming& timing) override {
    const backend::Status s = inner_.advance(timing);  // the fake in lockstep: timing zero
    timing = next ? next() : backend::TickTiming{};
    g_clock += static_cast<std::uint64_t>((0.001 + timing.lateness) * 1e9);
    skipped_time_ += 0.001 * timing.skipped;
    return s;
  }
  const backend::Error& lastError() const override { return inner_.lastError(); }
  void stop() override { inner_.stop(); }

  std::function<backend::TickTiming()> next;
  bool throw_on_read = false;

 private:
  backend::Backend& inner_;
  double skipped_time_ = 0.0;
};

backend::TickTiming lateBy(double seconds) {
  backend::TickTiming t;
  t.late = true;
  t.lateness = seconds;
  t.skipped = static_cast<std::uint32_t>(seconds / 0.001);
  return t;
}

backend::TickTiming onTime() {
  backend::TickTiming t;
  t.lateness = 30e-6;  // a wake-up latency
  return t;
}

class DeadlinePolicy : public ::testing::Test {
 protected:
  void SetUp() override { make(false); }
  void make(bool lockstep) {
    loop_.reset();
    if (fake_) ballast_backend_entry()->destroy(fake_);
    const profile::Profile p =
        profile::Profile::load(std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
    settings_ = profile::buildSettings(p, test::humanoid());
    // The policy at a robot's command gap, the schema's default (sim-flat allows its host 25 ms).
    settings_.max_command_gap = 0.01;
    settings_.initial_mode = Mode::kStandUp;
    settings_.stand_up_duration = 0.3;
    fake_ = ballast_backend_entry()->create();
    backend_ = std::make_unique<ScriptedBackend>(*fake_);
    backend::Config config;
    config.section_yaml = "{}";
    config.section_origin = "test:1";
    const std::string urdf = test::humanoidUrdf();
    config.urdf_path = urdf.c_str();
    config.period = 0.001;
    config.lockstep = true;  // the fake never sleeps; the schedule is the script's
    backend::Error error;
    ASSERT_TRUE(backend_->configure(config, error)) << error.message;
    ASSERT_TRUE(backend_->start(error));
    LoopOptions options;
    options.lockstep = lockstep;
    options.clock = &fakeClock;
    loop_ = std::make_unique<ControlLoop>(test::humanoid(), *backend_,
                                          std::make_shared<const ControlSettings>(settings_), options);
    backend_->next = onTime;
    ticks(500);
    ASSERT_EQ(loop_->status().mode, Mode::kStand);
  }
  void TearDown() override {
    loop_.reset();
    backend_.reset();
    if (fake_) ballast_backend_entry()->destroy(fake_);
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) loop_->guardedTick();
  }
  const Fault* fault(FaultKind kind) const {
    status_ = loop_->status();
    for (int i = 0; i < status_.faults.size; ++i)
      if (status_.faults.fault[i].kind == kind) return &status_.faults.fault[i];
    return nullptr;
  }

  ControlSettings settings_;
  backend::Backend* fake_ = nullptr;
  std::unique_ptr<ScriptedBackend> backend_;
  std::unique_ptr<ControlLoop> loop_;
  mutable LoopStatus status_;
};

TEST_F(DeadlinePolicy, LateTicksBelowTheFractionRideThroughAndAreCounted) {
  // The injection: one tick 3 ms late, then 2 ms late on 5 % of ticks, for 3 s.
  ASSERT_NEAR(settings_.max_late_fraction, 0.2, 1e-12);
  std::mt19937 random(7);
  int late = 0, skipped = 0, k = 0;
  backend_->next = [&] {
    ++k;
    backend::TickTiming t = onTime();
    if (k == 1 || std::uniform_real_distribution<double>(0, 1)(random) < 0.05) {
      t = lateBy(k == 1 ? 0.003 : 0.002);
      ++late;
      skipped += static_cast<int>(t.skipped);
    }
    return t;
  };
  ticks(3000);
  const LoopStatus s = loop_->status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.faults.size, 0);
  EXPECT_GT(late, 100);
  EXPECT_EQ(s.timing.late_ticks, static_cast<std::uint64_t>(late));
  EXPECT_EQ(s.tick_overruns, s.timing.late_ticks);
  EXPECT_EQ(s.timing.skipped_periods, static_cast<std::uint64_t>(skipped));
  EXPECT_NEAR(s.timing.lateness_max, 0.003, 1e-12);
  // 95 % of ticks on time (30 µs), 5 % at 2 ms: p50 at the wake-up latency, p99 at 2 ms.
  EXPECT_NEAR(s.timing.lateness_p50, 30e-6, 30e-6 * 0.05);
  EXPECT_NEAR(s.timing.lateness_p99, 0.002, 0.002 * 0.05);
  // Logged, but not once per tick: at most every 10 s.
  LoopEvent e;
  int warnings = 0;
  while (loop_->popEvent(e))
    if (e.warning && std::strstr(e.message, "late tick")) ++warnings;
  EXPECT_EQ(warnings, 1);
}

TEST_F(DeadlinePolicy, MoreLateTicksThanTheFractionInASecondIsAFault) {
  int k = 0;
  backend_->next = [&] { return ++k % 4 == 0 ? lateBy(0.0004) : onTime(); };  // 25 %
  ticks(1100);
  const Fault* f = fault(FaultKind::kLateTicks);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(status_.mode, Mode::kDamp);
  EXPECT_NE(std::strstr(f->message, "safety.max_late_fraction 0.20"), nullptr) << f->message;
  EXPECT_EQ(fault(FaultKind::kCommandGap), nullptr);  // the motors always had commands
}

TEST_F(DeadlinePolicy, AStallLongerThanTheCommandGapIsAFault) {
  int k = 0;
  backend_->next = [&] { return ++k == 100 ? lateBy(0.050) : onTime(); };
  ticks(200);
  const Fault* f = fault(FaultKind::kCommandGap);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(status_.mode, Mode::kDamp);
  EXPECT_NE(std::strstr(f->message, "51.0 ms without a command"), nullptr) << f->message;
  EXPECT_EQ(status_.timing.skipped_periods, 50u);
}

TEST_F(DeadlinePolicy, AStallWithinTheCommandGapRidesThrough) {
  int k = 0;
  backend_->next = [&] { return ++k == 100 ? lateBy(0.008) : onTime(); };
  ticks(200);
  EXPECT_EQ(loop_->status().faults.size, 0);
  EXPECT_EQ(loop_->status().mode, Mode::kStand);
  EXPECT_EQ(loop_->status().timing.late_ticks, 1u);
}

TEST_F(DeadlinePolicy, AHostStallTheSimulatedWorldWaitedForIsShownNotAFault) {
  // 72 ms in which the host did not run the control thread, twice within a second, then once
  // more: a simulation's world waited (no period skipped, the motors had their commands in the
  // world's time), so no fault; counted, the longest kept, logged at most once a second.
  int k = 0;
  backend_->next = [&] {
    backend::TickTiming t = onTime();
    if (++k == 100 || k == 300 || k == 1500) {
      t.lateness = k == 300 ? 0.030 : 0.072;
      t.host_stall = t.lateness;
    }
    return t;
  };
  ticks(2000);
  const LoopStatus s = loop_->status();
  EXPECT_EQ(s.faults.size, 0);
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.timing.host_stalls, 3u);
  EXPECT_NEAR(s.timing.host_stall_max, 0.072, 1e-12);
  EXPECT_EQ(s.timing.late_ticks, 0u);
  EXPECT_NEAR(s.timing.lateness_max, 0.072, 1e-12);  // still the schedule's lateness
  LoopEvent e;
  int warnings = 0;
  while (loop_->popEvent(e))
    if (e.warning && std::strstr(e.message, "host stall: the host did not run the control thread for 72.00 ms (the tick"))
      ++warnings;
  EXPECT_EQ(warnings, 2);  // ticks 100 and 1500; 300 within the same second as 100
}

TEST_F(DeadlinePolicy, LockstepHasNoDeadlines) {
  make(true);
  int k = 0;
  backend_->next = [&] { return ++k % 2 ? lateBy(0.5) : onTime(); };  // wall time means nothing
  ticks(500);
  EXPECT_EQ(loop_->status().faults.size, 0);
  EXPECT_EQ(loop_->status().timing.late_ticks, 0u);
}

TEST_F(DeadlinePolicy, AnExceptionInTheControlThreadDampsAndTheLoopGoesOn) {
  backend_->throw_on_read = true;
  ticks(10);
  const Fault* f = fault(FaultKind::kException);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(status_.mode, Mode::kDamp);
  EXPECT_NE(std::strstr(f->message, "the bus driver threw"), nullptr) << f->message;
  // The loop goes on: it answers a reset and stands the robot up again.
  const std::uint64_t before = loop_->status().ticks;
  OperatorCommand c;
  c.sequence = 1;
  c.kind = CommandKind::kReset;
  ASSERT_TRUE(loop_->submit(c));
  ticks(2);
  CommandReply r;
  ASSERT_TRUE(loop_->popReply(r));
  EXPECT_EQ(r.refusal, Refusal::kNone);
  EXPECT_EQ(loop_->status().mode, Mode::kPassive);
  EXPECT_EQ(loop_->status().ticks, before + 2);
}

class ThrowingPlanner : public Planner {
 public:
  void plan(const PlannerInput&, PlannerOutput&) override {
    throw std::out_of_range("injected: vector::_M_range_check");
  }
};

TEST_F(DeadlinePolicy, AnExceptionInThePlannerThreadIsAFault) {
  make(true);  // lockstep: the answer comes within the tick that posts
  ThrowingPlanner planner;
  const AttachedPlanner attached(*loop_, planner);
  ticks(50);
  const Fault* f = fault(FaultKind::kException);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(status_.mode, Mode::kDamp);
  EXPECT_NE(std::strstr(f->message, "planner thread: exception: injected"), nullptr)
      << f->message;
}

/// A planner whose thread blocks in its solve, as on a lock that a thread the machine does not
/// run holds: it answers (no plan) when released, or after 5 s.
class BlockedPlanner : public Planner {
 public:
  void plan(const PlannerInput&, PlannerOutput& out) override {
    std::unique_lock<std::mutex> lock(mutex_);
    released_.wait_for(lock, std::chrono::seconds(5), [this] { return release_; });
    out.valid = false;
    copyText(out.message, "released");
  }
  void release() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      release_ = true;
    }
    released_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable released_;
  bool release_ = false;
};

TEST_F(DeadlinePolicy, APlannerThatDoesNotRunIsAFaultThatSaysSo) {
  BlockedPlanner planner;
  {
    const AttachedPlanner attached(*loop_, planner);
    ticks(600);  // past the 0.5 s a plan may take while planning starts
    planner.release();
  }
  const Fault* f = fault(FaultKind::kPlanner);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(status_.mode, Mode::kDamp);
  // The solve's wall time and the planner thread's CPU time in it: blocked, it did not run.
  const char* solve = std::strstr(f->message, "the planner did not answer: in a solve for ");
  ASSERT_NE(solve, nullptr) << f->message;
  double wall = -1.0, cpu = -1.0;
  ASSERT_EQ(std::sscanf(solve, "the planner did not answer: in a solve for %lf ms, %lf ms of it on a CPU",
                        &wall, &cpu),
            2)
      << f->message;
  EXPECT_GT(wall, 0.0) << f->message;
  EXPECT_GE(cpu, 0.0) << f->message;
  EXPECT_LT(cpu, 0.5 * wall) << f->message;
}

}  // namespace
}  // namespace ballast::control
