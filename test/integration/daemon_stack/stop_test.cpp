// `ballast stop` after walking (issue 6 §3: at rest standing within 2 s) through ballastd's
// control core: the stop lands at an exact controller time here, so a sweep can reach every
// phase of the gait, which the CLI acceptance test (walk_stop.sh) only samples.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

double envOr(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

/// walk_stop.sh's test of rest: standing, ground-truth base speed under 0.05 m/s, the four
/// contact points on the ground.
bool atRest(const control::LoopStatus& s) {
  const double* v = s.truth.linear_velocity;
  return s.mode == control::Mode::kStand && v[0] * v[0] + v[1] * v[1] < 0.05 * 0.05 &&
         s.contacts[0] && s.contacts[1] && s.contacts[2] && s.contacts[3];
}

/// Development sweep (BALLAST_STOP_SWEEP=1): walking at BALLAST_STOP_VX (1.0) m/s for 4 s plus
/// a phase, stop; a fresh robot per phase (BALLAST_STOP_PHASES, 16, over the 0.8 s cycle) on
/// BALLAST_STOP_PROFILE (a path; sim-flat). Prints how long each took to come to rest.
TEST(StopSweep, OneRobotPerPhase) {
  if (!std::getenv("BALLAST_STOP_SWEEP")) GTEST_SKIP() << "set BALLAST_STOP_SWEEP=1";
  const char* profile = std::getenv("BALLAST_STOP_PROFILE");
  const int phases = static_cast<int>(envOr("BALLAST_STOP_PHASES", 16));
  const double period = 0.8;
  int late = 0;
  const int only = static_cast<int>(envOr("BALLAST_STOP_ONLY", -1));  // one phase, traced
  for (int k = 0; k < phases; ++k) {
    if (only >= 0 && k != only) continue;
    DaemonStack robot(profile ? std::string(profile)
                              : std::string(BALLAST_SOURCE_DIR) + "/profiles/sim-flat.yaml");
    ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
    ASSERT_TRUE(robot.run(0.5));
    ASSERT_EQ(robot.walk(envOr("BALLAST_STOP_VX", 1.0)), control::Refusal::kNone);
    const double t0 = robot.t();
    ASSERT_TRUE(robot.run(4.0 + k * period / phases));
    const double phase = std::fmod(robot.t() - t0, period);
    control::OperatorCommand stop;
    stop.kind = control::CommandKind::kStop;
    ASSERT_EQ(robot.command(stop), control::Refusal::kNone);
    const double stopped = robot.t();
    double rest = -1.0;
    bool fell = false;
    for (int tick = 0; tick < 6000 && rest < 0 && !fell; tick += 10) {
      fell = !robot.run(0.01);
      const control::LoopStatus s = robot.status();
      if (atRest(s)) rest = robot.t() - stopped;
      if (only >= 0 && tick % 50 == 0)
        std::printf("  t %.2f x %.3f vx %.3f vy %.3f z %.3f roll %.3f pitch %.3f contacts %d%d%d%d %s\n",
                    s.t - stopped, s.truth.position[0], s.truth.linear_velocity[0],
                    s.truth.linear_velocity[1], s.truth.position[2], s.truth.rpy[0], s.truth.rpy[1],
                    s.contacts[0], s.contacts[1], s.contacts[2], s.contacts[3],
                    control::modeName(s.mode));
    }
    const control::LoopStatus s = robot.status();
    std::printf("phase %.3f s: %s after %.2f s (mode %s, v %.3f %.3f, contacts %d%d%d%d%s%s)\n",
                phase, fell ? "FELL" : "at rest", fell ? s.t - stopped : rest,
                control::modeName(s.mode), s.truth.linear_velocity[0], s.truth.linear_velocity[1],
                s.contacts[0], s.contacts[1], s.contacts[2], s.contacts[3],
                s.faults.size ? ", " : "", s.faults.size ? s.faults.fault[0].message : "");
    late += !(rest >= 0.0 && rest <= 2.0);
  }
  EXPECT_EQ(late, 0);
}

}  // namespace
}  // namespace ballast::test
