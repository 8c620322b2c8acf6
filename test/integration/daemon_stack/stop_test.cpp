// Commands that land at any phase of the gait, through ballastd's control core. The CLI's
// acceptance tests (walk_stop.sh, walk.sh) send `ballast stop` and `ballast walk` at wall-clock
// times, so from run to run they meet the gait at another phase; here the command lands at an
// exact controller time, one fresh robot per phase, so every phase is tried in every run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

constexpr double kPeriod = 0.8;  // sim-flat's gait.period

/// walk_stop.sh's test of rest: standing, ground-truth base speed under 0.05 m/s, the four
/// contact points on the ground.
bool atRest(const control::LoopStatus& s) {
  const double* v = s.truth.linear_velocity;
  return s.mode == control::Mode::kStand && v[0] * v[0] + v[1] * v[1] < 0.05 * 0.05 &&
         s.contacts[0] && s.contacts[1] && s.contacts[2] && s.contacts[3];
}

struct StopResult {
  double phase = 0.0;  ///< s into the gait cycle when the stop landed
  bool fell = false;
  double rest = -1.0;  ///< s from the stop to rest, -1 if not within the time allowed
};

/// Walking at vx for `walk` s plus `offset`, then `ballast stop`; `trace` prints the stop.
StopResult stopAt(double vx, double walk, double offset, bool trace) {
  const char* profile = std::getenv("BALLAST_STOP_PROFILE");  // development: another profile
  DaemonStack robot(profile ? std::string(profile) : kDefaultProfile);
  StopResult r;
  EXPECT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  EXPECT_TRUE(robot.run(0.5));
  EXPECT_EQ(robot.walk(vx), control::Refusal::kNone);
  const double t0 = robot.t();
  if (!robot.run(walk + offset)) {
    r.fell = true;
    return r;
  }
  r.phase = std::fmod(robot.t() - t0, kPeriod);
  control::OperatorCommand stop;
  stop.kind = control::CommandKind::kStop;
  EXPECT_EQ(robot.command(stop), control::Refusal::kNone);
  const double stopped = robot.t();
  for (int tick = 0; tick < 4000 && r.rest < 0.0; tick += 10) {
    if (!robot.run(0.01)) {
      r.fell = true;
      break;
    }
    const control::LoopStatus s = robot.status();
    if (atRest(s)) r.rest = robot.t() - stopped;
    if (trace && tick % 50 == 0)
      std::printf("  t %.2f x %.3f vx %.3f vy %.3f z %.3f roll %.3f pitch %.3f contacts %d%d%d%d %s\n",
                  s.t - stopped, s.truth.position[0], s.truth.linear_velocity[0],
                  s.truth.linear_velocity[1], s.truth.position[2], s.truth.rpy[0], s.truth.rpy[1],
                  s.contacts[0], s.contacts[1], s.contacts[2], s.contacts[3],
                  control::modeName(s.mode));
  }
  const control::LoopStatus s = robot.status();
  std::printf("stop from %.1f m/s at phase %.3f s: %s %.2f s after the stop (mode %s, v %.3f %.3f%s%s)\n",
              vx, r.phase, r.fell ? "FELL" : r.rest >= 0.0 ? "at rest" : "not at rest",
              r.rest >= 0.0 ? r.rest : s.t - stopped, control::modeName(s.mode),
              s.truth.linear_velocity[0], s.truth.linear_velocity[1],
              s.faults.size ? ", " : "", s.faults.size ? s.faults.fault[0].message : "");
  return r;
}

/// Issue 6 §3 (walk_stop.sh) at every eighth of the gait cycle: `ballast stop` after walking at
/// 1.0 m/s and from 1.2 m/s (the fastest acceptance walk), at rest standing within 2 s.
/// One CTest test per speed and phase, so `ctest -j` runs them side by side (each ~3 s of CPU).
class StopAtPhase : public ::testing::TestWithParam<std::tuple<double, int>> {};

TEST_P(StopAtPhase, AtRestWithinTwoSeconds) {
  const auto [vx, k] = GetParam();
  const StopResult r = stopAt(vx, 3.0, k * kPeriod / 8, false);
  const double allowed = 2.0;
  EXPECT_FALSE(r.fell) << "fell after a stop from " << vx << " m/s at gait phase " << r.phase << " s";
  EXPECT_TRUE(r.rest >= 0.0 && r.rest <= allowed + 1e-9)
      << "stop from " << vx << " m/s at gait phase " << r.phase << " s: at rest after " << r.rest
      << " s";
}

INSTANTIATE_TEST_SUITE_P(Stop, StopAtPhase,
                         ::testing::Combine(::testing::Values(1.0, 1.2), ::testing::Range(0, 8)),
                         [](const auto& info) {
                           return "from_" + std::to_string(static_cast<int>(std::get<0>(info.param) * 10)) +
                                  "dm_s_phase_" + std::to_string(std::get<1>(info.param)) + "_of_8";
                         });

/// Development sweep (BALLAST_STOP_SWEEP=1): BALLAST_STOP_PHASES (16) phases from
/// BALLAST_STOP_VX (1.0) m/s after BALLAST_STOP_WALK (4) s; BALLAST_STOP_ONLY=k traces phase k.
TEST(StopSweep, OneRobotPerPhase) {
  if (!std::getenv("BALLAST_STOP_SWEEP")) GTEST_SKIP() << "set BALLAST_STOP_SWEEP=1";
  const int phases = static_cast<int>(envOr("BALLAST_STOP_PHASES", 16));
  const int only = static_cast<int>(envOr("BALLAST_STOP_ONLY", -1));
  int late = 0;
  for (int k = 0; k < phases; ++k) {
    if (only >= 0 && k != only) continue;
    const StopResult r = stopAt(envOr("BALLAST_STOP_VX", 1.0), envOr("BALLAST_STOP_WALK", 4.0),
                                k * kPeriod / phases, only >= 0);
    late += r.fell || !(r.rest >= 0.0 && r.rest <= 2.0);
  }
  EXPECT_EQ(late, 0);
}

/// Development sweep (BALLAST_WALK_SWEEP=1): `ballast walk` at BALLAST_WALK_VX (1.2) m/s sent
/// BALLAST_WALK_PHASES (8) offsets apart over a gait period after standing, 10 s each, the
/// forward velocity over the last 5 s (walk.sh's measure).
TEST(WalkSweep, OneRobotPerStart) {
  if (!std::getenv("BALLAST_WALK_SWEEP")) GTEST_SKIP() << "set BALLAST_WALK_SWEEP=1";
  const int phases = static_cast<int>(envOr("BALLAST_WALK_PHASES", 8));
  const double vx = envOr("BALLAST_WALK_VX", 1.2);
  int bad = 0;
  for (int k = 0; k < phases; ++k) {
    DaemonStack robot(kDefaultProfile);
    ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
    ASSERT_TRUE(robot.run(0.5 + k * kPeriod / phases));
    ASSERT_EQ(robot.walk(vx), control::Refusal::kNone);
    bool ok = robot.run(5.0);
    const control::LoopStatus a = robot.status();
    ok = ok && robot.run(5.0);
    const control::LoopStatus b = robot.status();
    const double v = (b.truth.position[0] - a.truth.position[0]) / (b.t - a.t);
    std::printf("walk %.1f m/s sent %.3f s later: %s, %.3f m/s over the last 5 s\n", vx,
                k * kPeriod / phases, ok ? "ok" : "FELL", v);
    bad += !ok || std::abs(v - vx) > 0.1;
  }
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace ballast::test
