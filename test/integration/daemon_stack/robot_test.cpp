// Robots other than the shipped humanoid, as a user brings them: URDFs from the generator
// (urdf/generate_humanoid.py, never copies of vendors' files) and a profile alone.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "test/integration/daemon_stack/daemon_stack.hpp"

namespace ballast::test {
namespace {

namespace fs = std::filesystem;

/// sim-flat on a generated URDF without toe, heel, IMU and lidar links: the profile places those
/// frames on the feet, the pelvis (test/integration/daemon/profiles/vendor-frames.yaml) and the
/// head, and locks both wrist_yaw joints straight.
std::string vendorProfile(const std::string& urdf) {
  const fs::path dir = fs::temp_directory_path() /
                       ("ballast-robot-test-" + std::to_string(getpid()) + "-" +
                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::create_directories(dir);
  const std::string path = (dir / "robot.yaml").string();
  std::ofstream(path) << "extends: " << BALLAST_SOURCE_DIR
                      << "/test/integration/daemon/profiles/vendor-frames.yaml\n"
                      << "robot:\n  urdf: " << TEST_URDF_DIR << "/" << urdf << ".urdf\n" << R"(
  locked_joints: {left_wrist_yaw: 0, right_wrist_yaw: 0}
  joint_groups:
    arms: [left_shoulder_pitch, left_shoulder_roll, left_shoulder_yaw, left_elbow, left_wrist_pitch,
           right_shoulder_pitch, right_shoulder_roll, right_shoulder_yaw, right_elbow, right_wrist_pitch]
backend:
  simbody:
    lidar: {frame: {link: head, offset: [0.08, 0, 0.10]}}
)";
  return path;
}

TEST(VendorRobot, PlacedFramesAndLockedWristsWalkHalfAMetreASecondForTenSeconds) {
  const std::string profile = vendorProfile("no_frame_links");
  DaemonStack robot(profile);
  EXPECT_EQ(robot.model().nj(), 22);
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  ASSERT_TRUE(robot.run(0.5));
  const double x0 = robot.status().truth.position[0];
  ASSERT_EQ(robot.walk(0.5, 0.0, 0.0, 10.0), control::Refusal::kNone);
  EXPECT_TRUE(robot.run(10.0)) << control::modeName(robot.status().mode);
  const double walked = robot.status().truth.position[0] - x0;
  std::printf("walked %.3f m in 10 s at 0.5 m/s\n", walked);
  EXPECT_GT(walked, 4.0);
  EXPECT_TRUE(robot.run(1.5));  // and stops on its feet when the command lapses
  fs::remove_all(fs::path(profile).parent_path());
}

TEST(VendorRobot, FeetWithoutCollisionBoxesStandOnTheContactPoints) {
  const std::string profile = vendorProfile("point_feet");
  DaemonStack robot(profile);
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  EXPECT_TRUE(robot.run(5.0)) << control::modeName(robot.status().mode);
  const control::LoopStatus s = robot.status();
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(s.contacts[c]) << c;
  fs::remove_all(fs::path(profile).parent_path());
}

}  // namespace
}  // namespace ballast::test
