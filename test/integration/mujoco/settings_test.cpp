// The mujoco backend's profile section: defaults, errors with file:line:column, the keys it
// shares with the simbody backend, and the header's key reference in step with the table.
#include <gtest/gtest.h>


#include "mujoco_settings.hpp"

namespace ballast::mujoco {
namespace {

std::string settingsError(const std::string& yaml, const std::string& origin = "sim.yaml:10") {
  try {
    parseMujocoSettings(yaml, origin);
  } catch (const SettingsError& e) {
    return e.what();
  }
  return "";
}

TEST(MujocoSettings, EmptySectionGivesTheTableDefaults) {
  const MujocoSettings s = parseMujocoSettings("", "sim.yaml:10");
  EXPECT_DOUBLE_EQ(s.friction, 0.8);
  EXPECT_EQ(s.substeps, 1);
  EXPECT_EQ(s.integrator, "euler");
  EXPECT_EQ(s.cone, "elliptic");
  EXPECT_EQ(s.contact_impedance, (Vec3d{0.9, 0.95, 0.001}));
  EXPECT_EQ(s.gravity, (Vec3d{0, 0, -9.81}));
  EXPECT_EQ(s.motor_latency_ticks, 0);
  EXPECT_TRUE(s.lidar_enabled);
  EXPECT_EQ(s.lidar_horizontal_rays, 180);
  EXPECT_EQ(s.imu_frame.link, "imu");
  EXPECT_EQ(s.initial_posture, "stand");
  EXPECT_TRUE(s.initial_joints.empty());
  EXPECT_TRUE(s.terrain_map.empty());
}

TEST(MujocoSettings, TheSensorAndLidarKeysFeedTheSharedModels) {
  const MujocoSettings s = parseMujocoSettings(
      "encoder_resolution: 0.001\njoint_velocity_noise: 0.02\ntorque_noise: 0.5\n"
      "imu: {gyro_noise_density: 0.01, gyro_bias: 0.005, accel_noise_density: 0.02,\n"
      "      accel_bias: 0.03, orientation_noise: 0.004}\n"
      "position_fix: {rate: 10, noise: 0.02}\n"
      "lidar: {rate: 20, horizontal_rays: 90, vertical_rays: 8, range_noise: 0.01}\n",
      "sim.yaml:10");
  const plugin::SensorNoise n = plugin::sensorNoise(s);
  EXPECT_DOUBLE_EQ(n.encoder_resolution, 0.001);
  EXPECT_DOUBLE_EQ(n.joint_velocity_noise, 0.02);
  EXPECT_DOUBLE_EQ(n.torque_noise, 0.5);
  EXPECT_DOUBLE_EQ(n.gyro_noise_density, 0.01);
  EXPECT_DOUBLE_EQ(n.gyro_bias, 0.005);
  EXPECT_DOUBLE_EQ(n.accel_noise_density, 0.02);
  EXPECT_DOUBLE_EQ(n.accel_bias, 0.03);
  EXPECT_DOUBLE_EQ(n.orientation_noise, 0.004);
  EXPECT_DOUBLE_EQ(n.position_fix_rate, 10);
  EXPECT_DOUBLE_EQ(n.position_fix_noise, 0.02);
  const plugin::LidarSettings l = plugin::lidarSettings(s);
  EXPECT_DOUBLE_EQ(l.rate, 20);
  EXPECT_EQ(l.horizontal_rays, 90);
  EXPECT_EQ(l.vertical_rays, 8);
  EXPECT_DOUBLE_EQ(l.range_noise, 0.01);
  EXPECT_EQ(l.link, "lidar");
  const plugin::LidarSettings mounted = plugin::lidarSettings(parseMujocoSettings(
      "lidar: {frame: {link: head, offset: [0.08, 0, 0.1], rpy: [0, 0.2, 0]}}\n", "sim.yaml:10"));
  EXPECT_EQ(mounted.link, "head");
  EXPECT_DOUBLE_EQ(mounted.offset[0], 0.08);
  EXPECT_DOUBLE_EQ(mounted.offset[2], 0.1);
  EXPECT_DOUBLE_EQ(mounted.rpy[1], 0.2);
}

TEST(MujocoSettings, ErrorsSayFileLineColumnKeyAndWhatIsWrong) {
  EXPECT_EQ(settingsError("friction: 0.5\nfriciton: 0.7\n"),
            "sim.yaml:11:1: friciton: unknown key (did you mean friction?)");
  EXPECT_EQ(settingsError("integrator: verlet\n"),
            "sim.yaml:10:13: integrator: expected one of euler|implicit, got 'verlet'");
  EXPECT_EQ(settingsError("substeps: 0\n"), "sim.yaml:10:11: substeps: 0 is out of range [1, 100]");
  EXPECT_EQ(settingsError("contact_impedance: [0.99, 0.9, 0.001]\n"),
            "sim.yaml:10:1: contact_impedance: dmin (0.99) is above dmax (0.9)");
  EXPECT_EQ(settingsError("lidar:\n  rate: -3\n"),
            "sim.yaml:11:9: lidar.rate: -3 is out of range [0.1, 100]");
  EXPECT_EQ(settingsError("- 1\n"),
            "sim.yaml:10:1: the mujoco backend section must be a map of keys");
}

TEST(MujocoSettings, SharedKeysHaveTheSimbodyBackendsDefaultsAndBounds) {
  // The keys both simulation backends know, as plugins/simbody/sim_settings.cpp declares them.
  struct Shared {
    const char* name;
    const char* defaultYaml;
    double min, max;
  };
  const Shared shared[] = {
      {"friction", "0.8", 0, 3},          {"foot_sphere_radius", "0.01", 1e-3, 0.05},
      {"foot_width", "0", 0, 0.5},        {"motor_latency_ticks", "0", 0, 64},
      {"torque_limit_scale", "1", 0, 10}, {"encoder_resolution", "0", 0, 0.1},
      {"imu.gyro_noise_density", "2.4e-4", 0, 1}, {"imu.accel_noise_density", "1.5e-3", 0, 10},
      {"lidar.rate", "10", 0.1, 100},     {"position_fix.noise", "0.01", 1e-5, 1},
      {"initial_clearance", "0", 0, 1000}, {"host.stall_at", "-1", -1, 1e6},
      {"overhang_height", "0.5", 0.05, 100},
  };
  for (const Shared& k : shared) {
    const SettingKey* key = nullptr;
    for (const SettingKey& candidate : mujocoSettingKeys())
      if (std::string(candidate.name) == k.name) key = &candidate;
    ASSERT_NE(key, nullptr) << k.name;
    EXPECT_STREQ(key->defaultYaml, k.defaultYaml) << k.name;
    EXPECT_EQ(key->min, k.min) << k.name;
    EXPECT_EQ(key->max, k.max) << k.name;
  }
}

}  // namespace
}  // namespace ballast::mujoco
