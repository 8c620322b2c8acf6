// The MuJoCo plugin as ballastd sees it: loaded by name through daemon/backend's loader, used
// only through plugins/backend_abi.hpp: what it says of the robot, determinism per seed, and
// configure errors that name the profile key (file:line:column) or the URDF.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "backend/plugin_loader.hpp"
#include "test/integration/imu_frame_check.hpp"
#include "terrain_maps.hpp"
#include "test/integration/simbody/sim_test_support.hpp"

namespace ballast::mujoco::test {
namespace {

using backend::BackendPtr;
using backend::Plugin;
using backend::Status;
using simbody::test::holdPosture;
using simbody::test::humanoidUrdfPath;
using simbody::test::SimConfig;

std::shared_ptr<Plugin> mujocoPlugin() {
  static const std::shared_ptr<Plugin> plugin = Plugin::load("mujoco");
  return plugin;
}

struct Recording {
  std::vector<backend::Sensors> samples;
  std::vector<std::vector<float>> scans;
};

/// `ticks` lockstep ticks holding the initial posture, with a push on a hand and noisy sensors.
Recording runFor(std::uint64_t seed, int ticks) {
  SimConfig config;
  config.seed = seed;
  config.yaml = "imu: {gyro_bias: 0.01, accel_bias: 0.05, orientation_noise: 0.001}\n"
                "joint_velocity_noise: 0.01\nencoder_resolution: 1.0e-4\n"
                "lidar: {rate: 50, horizontal_rays: 36, vertical_rays: 4, range_noise: 0.005}\n";
  BackendPtr sim = mujocoPlugin()->create();
  backend::Error error;
  EXPECT_TRUE(sim->configure(config.config(), error)) << error.message;
  EXPECT_TRUE(sim->start(error)) << error.message;
  Recording run;
  backend::Sensors s;
  sim->read(s);
  backend::Commands cmd;
  holdPosture(sim->capabilities(), s.q, cmd);
  backend::Push push;
  std::strcpy(push.body, "left_hand");
  push.force[1] = 20;
  push.duration = 0.05;
  EXPECT_TRUE(sim->push(push, error)) << error.message;
  for (int k = 0; k < ticks; ++k) {
    EXPECT_EQ(sim->write(cmd), Status::kOk);
    EXPECT_EQ(sim->advance(), Status::kOk) << sim->lastError().message;
    EXPECT_EQ(sim->read(s), Status::kOk);
    run.samples.push_back(s);
    backend::PointCloudView scan;
    if (sim->lidarScan(scan)) run.scans.emplace_back(scan.xyz, scan.xyz + 3 * scan.count);
  }
  return run;
}

bool sameBits(const double* a, const double* b, int n) {
  return std::memcmp(a, b, sizeof(double) * static_cast<std::size_t>(n)) == 0;
}

TEST(MujocoPlugin, LoadsByNameAndDescribesTheRobot) {
  const auto plugin = mujocoPlugin();
  EXPECT_STREQ(plugin->entry().name, "mujoco");
  EXPECT_NE(plugin->path().find("lib/ballast/libballast_backend_mujoco.so"), std::string::npos);
  BackendPtr sim = plugin->create();
  SimConfig config;
  backend::Error error;
  ASSERT_TRUE(sim->configure(config.config(), error)) << error.message;
  const backend::Capabilities& caps = sim->capabilities();
  EXPECT_STREQ(caps.name, "mujoco");
  EXPECT_TRUE(caps.simulation && caps.lockstep && caps.ground_truth && caps.lidar && caps.disturbance);
  EXPECT_FALSE(caps.position_fix);
  ASSERT_EQ(caps.num_joints, 24);
  EXPECT_STREQ(caps.joint_names[0], "left_hip_yaw");
  EXPECT_STREQ(caps.joint_names[5], "left_ankle_roll");
  EXPECT_STREQ(caps.joint_names[6], "right_hip_yaw");
  EXPECT_STREQ(caps.joint_names[12], "left_shoulder_pitch");
  EXPECT_STREQ(caps.joint_names[23], "right_wrist_pitch");
}

TEST(MujocoPlugin, TheSameSeedRepeatsBitForBitAnotherSeedChangesOnlyTheNoise) {
  const Recording a = runFor(42, 300), b = runFor(42, 300), c = runFor(43, 300);
  ASSERT_EQ(a.samples.size(), 300u);
  ASSERT_EQ(a.scans.size(), 15u);  // 50 Hz for 0.3 s
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    const backend::Sensors &x = a.samples[k], &y = b.samples[k];
    ASSERT_TRUE(sameBits(x.q, y.q, 24) && sameBits(x.dq, y.dq, 24) && sameBits(x.tau, y.tau, 24))
        << "tick " << k;
    ASSERT_TRUE(sameBits(x.imu.angular_velocity, y.imu.angular_velocity, 3) &&
                sameBits(x.imu.linear_acceleration, y.imu.linear_acceleration, 3) &&
                sameBits(x.imu.orientation, y.imu.orientation, 4))
        << "tick " << k;
    ASSERT_TRUE(sameBits(x.truth.base_position, y.truth.base_position, 3) &&
                sameBits(x.truth.base_linear_velocity, y.truth.base_linear_velocity, 3) &&
                sameBits(&x.truth.contact_force[0][0], &y.truth.contact_force[0][0], 3 * 4))
        << "tick " << k;
  }
  EXPECT_EQ(a.scans, b.scans);
  int differentImu = 0;
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    const backend::Sensors &x = a.samples[k], &z = c.samples[k];
    differentImu += !sameBits(x.imu.angular_velocity, z.imu.angular_velocity, 3);
    EXPECT_TRUE(sameBits(x.truth.base_position, z.truth.base_position, 3)) << "tick " << k;
  }
  EXPECT_EQ(differentImu, 300);
  EXPECT_NE(a.scans, c.scans);
}

TEST(MujocoPlugin, TheImuIsWhereTheRobotsImuFrameIsUnlessTheSectionPlacesIt) {
  ballast::test::expectTheImuWhereConfigPutsIt(*mujocoPlugin());
}

TEST(MujocoPlugin, ConfigureErrorsNameTheFileLineAndKey) {
  BackendPtr sim = mujocoPlugin()->create();
  backend::Error error;
  SimConfig config;
  config.origin = "profiles/sim.yaml:40";
  config.yaml = "friction: 0.5\nlidar:\n  rate: -3\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "profiles/sim.yaml:42:9: lidar.rate: -3 is out of range [0.1, 100]");

  config.yaml = "initial_joints:\n  left_kne: 0.3\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_EQ(std::string(error.message),
            "profiles/sim.yaml:41:3: initial_joints.left_kne: " + config.urdf +
                " has no movable joint 'left_kne'");

  config.yaml = "initial_joints: {left_knee: 3.0}\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_NE(std::string(error.message).find("profiles/sim.yaml:40:18: initial_joints.left_knee: "
                                            "3.000000 rad is outside the joint's limits [0.000000, 2.400000]"),
            std::string::npos)
      << error.message;

  config.yaml = "terrain_map: nowhere.bt\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "profiles/sim.yaml:40:1: terrain_map: cannot read nowhere.bt "
                              "(nor profiles/nowhere.bt)");

  config.yaml = "imu: {frame: chest}\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_EQ(std::string(error.message),
            "profiles/sim.yaml:40:7: imu.frame: " + config.urdf + " has no link 'chest'");

  config.yaml = "substeps: 2\ncontact_timeconst: 0.0008\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "profiles/sim.yaml:41:1: contact_timeconst: must be at least 2 "
                              "timesteps (0.001 s): MuJoCo's soft contact is unstable faster than that");

  config.yaml = "";
  config.map = "/no/such/map.bt";  // the planner's map, from Config
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "/no/such/map.bt: cannot read the terrain map");

  config.map = "";
  config.urdf = "/no/robot.urdf";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "/no/robot.urdf: cannot read the URDF");

  config.urdf = ::testing::TempDir() + "broken.urdf";
  std::ofstream(config.urdf) << "<robot name='x'><link name='a'>\n";
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_EQ(std::string(error.message), config.urdf + ": urdfdom could not parse the URDF");

  config.urdf = humanoidUrdfPath();
  config.period = 0;
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message, "Config::period 0.000000 s: the control period must be in (0, 0.1] s");

  EXPECT_FALSE(sim->start(error));
  EXPECT_STREQ(error.message, "mujoco: start() before a successful configure()");
  backend::Sensors s;
  EXPECT_EQ(sim->read(s), Status::kFault);
}

TEST(MujocoPlugin, ArmatureComesFromTheControllersJointModels) {
  BackendPtr sim = mujocoPlugin()->create();
  SimConfig config;
  backend::Config c = config.config();
  backend::JointModel joints[2];
  joints[0].name = "left_knee";
  joints[0].armature = -1;
  c.joints = joints;
  c.num_joint_models = 1;
  backend::Error error;
  EXPECT_FALSE(sim->configure(c, error));
  EXPECT_STREQ(error.message, "Config::joints: joint left_knee: armature must be finite and >= 0");
  joints[0].armature = 0.02;
  joints[1].name = "tail";
  joints[1].armature = 0.01;
  c.num_joint_models = 2;
  EXPECT_FALSE(sim->configure(c, error));
  EXPECT_EQ(std::string(error.message),
            "Config::joints: " + config.urdf + " has no movable joint 'tail' to give an armature");
  c.num_joint_models = 1;
  EXPECT_TRUE(sim->configure(c, error)) << error.message;
}

TEST(MujocoPlugin, ContactFramesMustBeLinksOfTheRobot) {
  BackendPtr sim = mujocoPlugin()->create();
  SimConfig config;
  backend::Config c = config.config();
  const char* frames[] = {"left_toe", "left_elbow_pad"};
  c.contact_frames = frames;
  c.num_contacts = 2;
  backend::Error error;
  EXPECT_FALSE(sim->configure(c, error));
  EXPECT_EQ(std::string(error.message),
            config.urdf + ": no link 'left_elbow_pad' (contact frame 1)");
  c.num_contacts = 0;
  EXPECT_FALSE(sim->configure(c, error));
  EXPECT_NE(std::string(error.message).find("no contact frames given"), std::string::npos);
}

TEST(MujocoPlugin, AMapWithoutGroundUnderTheRobotIsRefused) {
  const std::string path = ::testing::TempDir() + "mujoco-island.bt";
  const auto tree = maps::makeTerrainMap([](double, double) { return 0.0; }, 0.05, {4, 6, -1, 1});
  std::string message;
  ASSERT_TRUE(maps::writeTerrainMap(*tree, path, message)) << message;
  BackendPtr sim = mujocoPlugin()->create();
  SimConfig config;
  config.origin = "profiles/sim.yaml:40";
  config.yaml = "floor: false\n";
  config.map = path;
  backend::Error error;
  EXPECT_FALSE(sim->configure(config.config(), error));
  EXPECT_STREQ(error.message,
               "profiles/sim.yaml:40: initial_xy: no terrain under the robot at (0.000000, 0.000000)");
  config.yaml = "floor: false\ninitial_xy: [5, 0]\n";
  EXPECT_TRUE(sim->configure(config.config(), error)) << error.message;
}

}  // namespace
}  // namespace ballast::mujoco::test
