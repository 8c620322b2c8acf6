// Lockstep is a simulation: the same profile and seed give the same robot, bit for bit, however
// busy the machine is (the planner answers on its own thread, its plan is taken at a fixed
// controller time). A test that falls at one phase must fall there every run.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>
#include <vector>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

/// The ground-truth base after standing up and walking at 1.0 m/s for 3 s.
std::vector<double> walkAndRecord() {
  DaemonStack robot(kDefaultProfile);
  EXPECT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  EXPECT_TRUE(robot.run(0.3));
  EXPECT_EQ(robot.walk(1.0), control::Refusal::kNone);
  EXPECT_TRUE(robot.run(3.0));
  const control::LoopStatus s = robot.status();
  std::vector<double> out = {s.t};
  for (int i = 0; i < 3; ++i) out.push_back(s.truth.position[i]);
  for (int i = 0; i < 3; ++i) out.push_back(s.truth.rpy[i]);
  for (int i = 0; i < 3; ++i) out.push_back(s.truth.linear_velocity[i]);
  return out;
}

TEST(Lockstep, TwoRunsAreBitIdenticalEvenWhenTheMachineIsBusy) {
  const std::vector<double> quiet = walkAndRecord();
  // The second run with two threads spinning beside it: the planner's threads are delayed,
  // woken late and take the nodes in another order.
  std::atomic<bool> stop{false};
  std::vector<std::thread> load;
  for (int i = 0; i < 2; ++i)
    load.emplace_back([&] {
      volatile double x = 0;
      while (!stop) x = x + 1.0;
    });
  const std::vector<double> busy = walkAndRecord();
  stop = true;
  for (auto& t : load) t.join();
  ASSERT_EQ(quiet.size(), busy.size());
  for (std::size_t i = 0; i < quiet.size(); ++i)
    EXPECT_EQ(std::memcmp(&quiet[i], &busy[i], sizeof(double)), 0)
        << "entry " << i << ": " << quiet[i] << " against " << busy[i];
}

}  // namespace
}  // namespace ballast::test
