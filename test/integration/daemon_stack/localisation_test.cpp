// The estimator with a localisation source (issue 7: "a correction input for lidar or other
// odometry when a backend provides one"): the Simbody backend's position fixes (10 per second,
// 1 cm) fused by ballastd's control core while the robot walks on its estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

TEST(Localisation, PositionFixesHoldTheEstimateOnTheTruthWhileWalking) {
  const std::filesystem::path profile =
      std::filesystem::temp_directory_path() /
      ("ballast-localisation-" + std::to_string(getpid()) + ".yaml");
  // sim-flat's simulated robot sends the fixes; this profile fuses them.
  std::ofstream(profile) << "extends: " << BALLAST_SOURCE_DIR << "/profiles/sim-flat.yaml\n"
                         << "estimator:\n  position_fix: true\n";
  DaemonStack robot(profile.string());
  std::filesystem::remove(profile);
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  ASSERT_TRUE(robot.run(0.5));
  ASSERT_EQ(robot.walk(1.0), control::Refusal::kNone);
  const double t0 = robot.t();
  const std::uint64_t fixes0 = robot.status().position_fixes;
  double worst = 0, distance = 0, sumSquares = 0;
  int samples = 0;
  control::LoopStatus last = robot.status();
  for (int k = 0; k < 2000; ++k) {  // 20 s
    ASSERT_TRUE(robot.run(0.01)) << "fell at t " << robot.t();
    const control::LoopStatus s = robot.status();
    const double e = std::hypot(s.base.position[0] - s.truth.position[0],
                                s.base.position[1] - s.truth.position[1]);
    worst = std::max(worst, e);
    sumSquares += e * e;
    ++samples;
    distance += std::hypot(s.truth.position[0] - last.truth.position[0],
                           s.truth.position[1] - last.truth.position[1]);
    last = s;
  }
  const double fused = static_cast<double>(robot.status().position_fixes - fixes0);
  std::printf("walked %.1f m in %.1f s: horizontal estimate error RMS %.4f m, worst %.4f m; "
              "%.0f fixes fused\n",
              distance, robot.t() - t0, std::sqrt(sumSquares / samples), worst, fused);
  EXPECT_GT(distance, 15.0);
  EXPECT_NEAR(fused, 10.0 * (robot.t() - t0), 2.0);
  // Leg odometry alone may drift 2 % of the distance (40 cm here); with the fixes the error
  // stays at the fixes' own scale.
  EXPECT_LT(worst, 0.03);
}

}  // namespace
}  // namespace ballast::test
