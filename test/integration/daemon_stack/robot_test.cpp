// Robots other than the shipped humanoid, as a user brings them: URDFs from the generator
// (urdf/generate_humanoid.py, never copies of vendors' files) and a profile alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "main/describe_robot.hpp"
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

/// The generator's other robots, each with its profile (test/integration/daemon/profiles/
/// *.yaml.in) and its URDF written as vendors write theirs: each stands up and stands for 5 s on
/// its four contact points, controlling the joints it says. legs-of-5 (legs without hip yaw) and
/// hip-yaws-locked (the humanoid with both hip yaws locked) stand on feet that cannot yaw
/// relative to the pelvis: the relative yaw of the feet is a nearly dependent row of the task
/// stack's physics level, which the hierarchical QP counts as dependent or damps (before, it was
/// solved exactly, with joint accelerations of thousands of rad/s², and the robot fell in 0.8 s).
struct Variant {
  const char* profile;
  int joints;  ///< the model's joints once the profile's and the URDF's own locks are applied
};

class RobotVariant : public ::testing::TestWithParam<Variant> {};

TEST_P(RobotVariant, StandsOnItsContactPoints) {
  DaemonStack robot(std::string(TEST_PROFILE_DIR) + "/" + GetParam().profile + ".yaml");
  EXPECT_EQ(robot.model().nj(), GetParam().joints);
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  EXPECT_TRUE(robot.run(5.0)) << control::modeName(robot.status().mode);
  const control::LoopStatus s = robot.status();
  EXPECT_EQ(s.mode, control::Mode::kStand);
  for (int c = 0; c < 4; ++c) EXPECT_TRUE(s.contacts[c]) << c;
  EXPECT_GT(s.truth.position[2], 0.6);  // the base where standing puts it, not fallen
}

INSTANTIATE_TEST_SUITE_P(
    Robots, RobotVariant,
    ::testing::Values(Variant{"hips-pitch-roll-yaw", 24}, Variant{"joints-29", 24},
                      Variant{"mass-35", 24}, Variant{"hips-pitch-roll-yaw-mujoco", 24},
                      Variant{"joints-29-mujoco", 24}, Variant{"mass-35-mujoco", 24},
                      Variant{"legs-of-5", 22}, Variant{"legs-of-5-mujoco", 22},
                      Variant{"hip-yaws-locked", 22}, Variant{"hip-yaws-locked-mujoco", 22}),
    [](const ::testing::TestParamInfo<Variant>& info) {
      std::string name = info.param.profile;
      for (char& c : name)
        if (c == '-') c = '_';
      return name;
    });

/// The robots whose feet cannot yaw relative to the pelvis (legs of 5 joints, and the humanoid
/// with both hip yaws locked) walk straight ahead and sideways: walking needs no turn of the feet.
/// Every foot's yaw is then the base's, which a standing foot holds; the planner's contact
/// conditions and the whole-body controller's rows leave it out (before, they asked the legs for
/// it through the small leverage of the hip roll: plans of 10-900 rad/s, the weight shift stood
/// the legs up, and the robot fell within 1 s of the walk command).
struct Walk {
  const char* profile;
  double vx, vy;  ///< m/s, commanded
};

class RobotVariantWalk : public ::testing::TestWithParam<Walk> {};

TEST_P(RobotVariantWalk, WalksAtTheCommandedVelocity) {
  const Walk w = GetParam();
  DaemonStack robot(std::string(TEST_PROFILE_DIR) + "/" + w.profile + ".yaml");
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  ASSERT_TRUE(robot.run(0.5));
  ASSERT_EQ(robot.walk(w.vx, w.vy, 0.0, 7.0), control::Refusal::kNone);
  ASSERT_TRUE(robot.run(3.0)) << control::modeName(robot.status().mode) << " at t " << robot.t();
  const control::LoopStatus from = robot.status();
  ASSERT_TRUE(robot.run(4.0)) << control::modeName(robot.status().mode) << " at t " << robot.t();
  const control::LoopStatus to = robot.status();
  // The mean velocity over the last 4 s, in the heading the robot started with (yaw ~ 0).
  const double vx = (to.truth.position[0] - from.truth.position[0]) / 4.0;
  const double vy = (to.truth.position[1] - from.truth.position[1]) / 4.0;
  std::printf("%s: commanded (%.2f, %.2f) m/s, walked (%.3f, %.3f) m/s, yaw %.3f rad\n", w.profile,
              w.vx, w.vy, vx, vy, to.truth.rpy[2]);
  EXPECT_NEAR(vx, w.vx, 0.1);
  EXPECT_NEAR(vy, w.vy, 0.1);
  EXPECT_LT(std::abs(to.truth.rpy[2]), 0.2);  // it went straight: its feet cannot turn back
  EXPECT_TRUE(robot.run(2.0)) << "stopping";  // the command lapses at 7 s: it stops on its feet
  EXPECT_EQ(robot.status().mode, control::Mode::kStand);
}

INSTANTIATE_TEST_SUITE_P(
    Robots, RobotVariantWalk,
    ::testing::Values(Walk{"legs-of-5", 0.4, 0.0}, Walk{"legs-of-5-mujoco", 0.4, 0.0},
                      Walk{"legs-of-5", 0.0, 0.2}, Walk{"legs-of-5-mujoco", 0.0, 0.2},
                      Walk{"hip-yaws-locked", 0.4, 0.0}, Walk{"hip-yaws-locked-mujoco", 0.4, 0.0}),
    [](const ::testing::TestParamInfo<Walk>& info) {
      std::string name = info.param.profile;
      for (char& c : name)
        if (c == '-') c = '_';
      return name + (info.param.vy != 0.0 ? "_sideways" : "_forward");
    });

/// The robot whose legs have no hip yaw cannot turn (its feet stay parallel to the pelvis: a yaw
/// rate could only be walked as a straight line): walk with a yaw rate and pose with a yaw are
/// refused with the reason, and it keeps standing. (It walks straight: RobotVariantWalk.)
TEST(LegsOf5, RefusesToTurnAndSaysWhy) {
  DaemonStack robot(std::string(TEST_PROFILE_DIR) + "/legs-of-5.yaml");
  EXPECT_FALSE(robot.settings().feet_cannot_yaw.empty());
  ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
  ASSERT_TRUE(robot.run(0.5));
  EXPECT_EQ(robot.walk(0.4, 0.0, 0.2, 5.0), control::Refusal::kOutOfRange);
  EXPECT_TRUE(robot.run(1.0));
  EXPECT_EQ(robot.status().mode, control::Mode::kStand);
}

/// An IMU mounted turned and off the pelvis's origin, placed by robot.imu_frame alone: the
/// simulation puts its IMU there (Config::imu_frame) and the estimator reads it there, so the
/// estimate of the base follows the truth standing and walking.
class TurnedImu : public ::testing::TestWithParam<const char*> {};

TEST_P(TurnedImu, TheEstimatorGivenTheSameFrameFollowsTheBase) {
  const fs::path dir = fs::temp_directory_path() /
                       ("ballast-turned-imu-" + std::to_string(getpid()) + "-" + GetParam());
  fs::create_directories(dir);
  const std::string profile = (dir / "robot.yaml").string();
  std::ofstream(profile) << "extends: " << BALLAST_SOURCE_DIR << "/profiles/" << GetParam()
                         << ".yaml\nrobot:\n  imu_frame: {link: pelvis, offset: [0.03, -0.02, 0.05], "
                            "rpy: [0.1, 0, 1.5708]}\n";
  {
    DaemonStack robot(profile);
    ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
    ASSERT_TRUE(robot.run(1.0));
    ASSERT_EQ(robot.walk(0.4, 0.0, 0.0, 3.0), control::Refusal::kNone);
    double worst[3] = {};  // position, velocity, tilt
    for (int k = 0; k < 30; ++k) {
      ASSERT_TRUE(robot.run(0.1)) << control::modeName(robot.status().mode);
      const control::LoopStatus s = robot.status();
      for (int i = 0; i < 3; ++i) {
        worst[0] = std::max(worst[0], std::abs(s.base.position[i] - s.truth.position[i]));
        worst[1] = std::max(worst[1], std::abs(s.base.linear_velocity[i] - s.truth.linear_velocity[i]));
      }
      for (int i = 0; i < 2; ++i) worst[2] = std::max(worst[2], std::abs(s.base.rpy[i] - s.truth.rpy[i]));
    }
    const control::LoopStatus s = robot.status();
    std::printf("%s: walked %.2f m; estimate off by at most %.3f m, %.3f m/s, %.4f rad of tilt\n",
                GetParam(), s.truth.position[0], worst[0], worst[1], worst[2]);
    EXPECT_GT(s.truth.position[0], 0.8);
    EXPECT_LT(worst[0], 0.05);
    EXPECT_LT(worst[1], 0.15);
    EXPECT_LT(worst[2], 0.02);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Simulations, TurnedImu, ::testing::Values("sim-flat", "sim-flat-mujoco"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param) == "sim-flat" ? "simbody" : "mujoco";
                         });

/// ballastd --describe-robot's starter profile, as a user saves it, runs the robot: it passes the
/// checks of a start and the robot stands up and stands on the contact points it placed.
class StarterProfile : public ::testing::TestWithParam<const char*> {};

TEST_P(StarterProfile, StandsTheRobotItDescribes) {
  const std::string urdf = std::string(TEST_URDF_DIR) + "/" + GetParam() + ".urdf";
  const fs::path dir = fs::temp_directory_path() /
                       ("ballast-starter-" + std::to_string(getpid()) + "-" + GetParam());
  fs::create_directories(dir);
  const std::string profile = (dir / "robot.yaml").string();
  std::ofstream(profile) << daemon::describeRobot(urdf);
  {
    DaemonStack robot(profile);
    ASSERT_TRUE(robot.waitForMode(control::Mode::kStand, 5.0));
    EXPECT_TRUE(robot.run(5.0)) << control::modeName(robot.status().mode);
    const control::LoopStatus s = robot.status();
    EXPECT_EQ(s.mode, control::Mode::kStand);
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(s.contacts[c]) << c;
  }
  fs::remove_all(dir);
}

// mass_35's feet are a 2 mm sphere each: its soles are guessed from the feet's inertia (the
// starter profile says to measure them).
INSTANTIATE_TEST_SUITE_P(Robots, StarterProfile,
                         ::testing::Values("no_frame_links", "hips_pitch_roll_yaw", "joints_29",
                                           "mass_35"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param);
                         });

}  // namespace
}  // namespace ballast::test
