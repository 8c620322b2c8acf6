// Walking onto the stage (DESIGN: 15 cm, from the lidar map) through ballastd's control core.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

/// Development run (BALLAST_STAGE=1): walks at BALLAST_STAGE_VX (0.3) m/s towards the stage of
/// BALLAST_STAGE_PROFILE (sim-stage) and prints the base every 0.25 s.
TEST(StageWalk, Development) {
  if (!std::getenv("BALLAST_STAGE")) GTEST_SKIP() << "set BALLAST_STAGE=1";
  const char* p = std::getenv("BALLAST_STAGE_PROFILE");
  DaemonStack robot(p ? p : std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-stage.yaml");
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  ASSERT_TRUE(robot.run(0.5));
  const char* vx = std::getenv("BALLAST_STAGE_VX");
  ASSERT_EQ(robot.walk(vx ? std::atof(vx) : 0.3), control::Refusal::kNone);
  bool ok = true;
  const char* every = std::getenv("BALLAST_STAGE_PRINT");
  const double step = every ? std::atof(every) : 0.25;
  for (int k = 0; k < static_cast<int>(15.0 / step) && ok; ++k) {
    ok = robot.run(step);
    const control::LoopStatus s = robot.status();
    std::printf("t %.2f x %.3f z %.3f (est %.3f) pitch %.3f contacts %d%d%d%d mode %s\n", s.t,
                s.truth.position[0], s.truth.position[2], s.base.position[2], s.truth.rpy[1],
                s.contacts[0], s.contacts[1], s.contacts[2], s.contacts[3], control::modeName(s.mode));
  }
  const control::LoopStatus s = robot.status();
  for (int i = 0; i < s.faults.size; ++i) std::printf("fault: %s\n", s.faults.fault[i].message);
  EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace ballast::test
