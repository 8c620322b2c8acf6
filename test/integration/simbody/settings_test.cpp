// The simbody backend's profile section: defaults, every kind of error with file:line:column,
// and the header's key reference in step with the table.
#include <gtest/gtest.h>

#include <cstring>

#include "sim_settings.hpp"

namespace ballast::simbody {
namespace {

std::string errorOf(const std::string& yaml, const std::string& origin = "sim.yaml:10") {
  try {
    parseSimSettings(yaml, origin);
  } catch (const SettingsError& e) {
    return e.what();
  }
  return "";
}

TEST(SimSettings, EmptySectionGivesTheTableDefaults) {
  const SimSettings s = parseSimSettings("", "sim.yaml:10");
  EXPECT_DOUBLE_EQ(s.friction, 0.8);
  EXPECT_DOUBLE_EQ(s.contact_stiffness, 2e7);
  EXPECT_EQ(s.integrator, "semi_explicit_euler2");
  EXPECT_EQ(s.gravity, (Vec3d{0, 0, -9.81}));
  EXPECT_EQ(s.motor_latency_ticks, 0);
  EXPECT_TRUE(s.lidar_enabled);
  EXPECT_EQ(s.lidar_horizontal_rays, 180);
  EXPECT_EQ(s.imu_frame.link, "imu");
  EXPECT_EQ(s.initial_posture, "stand");
  EXPECT_TRUE(s.initial_joints.empty());
  EXPECT_TRUE(s.terrain_map.empty());
}

TEST(SimSettings, ValuesAndNestedGroupsAreRead) {
  const SimSettings s = parseSimSettings(
      "friction: 0.5\n"
      "integrator: rkm\n"
      "gravity: [0, 0, -1.62]\n"
      "motor_latency_ticks: 3\n"
      "initial_joints: {left_knee: 1.2, right_elbow: -0.5}\n"
      "imu:\n"
      "  gyro_bias: 0.01\n"
      "lidar:\n"
      "  enabled: no\n"
      "  rate: 20\n",
      "sim.yaml:10");
  EXPECT_DOUBLE_EQ(s.friction, 0.5);
  EXPECT_EQ(s.integrator, "rkm");
  EXPECT_DOUBLE_EQ(s.gravity[2], -1.62);
  EXPECT_EQ(s.motor_latency_ticks, 3);
  EXPECT_DOUBLE_EQ(s.initial_joints.at("left_knee"), 1.2);
  EXPECT_DOUBLE_EQ(s.initial_joints.at("right_elbow"), -0.5);
  EXPECT_DOUBLE_EQ(s.imu_gyro_bias, 0.01);
  EXPECT_FALSE(s.lidar_enabled);
  EXPECT_DOUBLE_EQ(s.lidar_rate, 20);
  EXPECT_EQ(s.where("lidar.rate"), "sim.yaml:19:3: lidar.rate: ");
  EXPECT_EQ(s.where("initial_joints.right_elbow"),
            "sim.yaml:14:34: initial_joints.right_elbow: ");
  EXPECT_EQ(s.where("accuracy"), "sim.yaml:10: accuracy: ");  // not given: the section
}

TEST(SimSettings, ErrorsSayFileLineColumnKeyAndWhatIsWrong) {
  // Lines count from the section's origin line (10): YAML line 0 is line 10.
  EXPECT_EQ(errorOf("friction: 0.5\nfriciton: 0.7\n"),
            "sim.yaml:11:1: friciton: unknown key (did you mean friction?)");
  EXPECT_EQ(errorOf("lidar:\n  rays: 5\n"),
            "sim.yaml:11:3: lidar.rays: unknown key (did you mean lidar.rate?)");
  EXPECT_EQ(errorOf("wobble: 1\n"), "sim.yaml:10:1: wobble: unknown key");
  EXPECT_EQ(errorOf("friction: 0.5\nimu: {gyro_bias: 0}\nfriction: 0.6\n"),
            "sim.yaml:12:1: friction: given twice (first at sim.yaml:10:1)");
  EXPECT_EQ(errorOf("friction: lots\n"), "sim.yaml:10:11: friction: expected a number, got 'lots'");
  EXPECT_EQ(errorOf("friction: 7\n"), "sim.yaml:10:11: friction: 7 is out of range [0, 3]");
  EXPECT_EQ(errorOf("accuracy: .nan\n"),
            "sim.yaml:10:11: accuracy: .nan is out of range [1e-08, 0.1]");
  EXPECT_EQ(errorOf("motor_latency_ticks: 1.5\n"),
            "sim.yaml:10:22: motor_latency_ticks: expected an integer, got '1.5'");
  EXPECT_EQ(errorOf("floor: maybe\n"), "sim.yaml:10:8: floor: expected true or false, got 'maybe'");
  EXPECT_EQ(errorOf("integrator: euler\n"),
            "sim.yaml:10:13: integrator: expected one of "
            "semi_explicit_euler2|semi_explicit_euler|rkm|rk3|rkf|verlet, got 'euler'");
  EXPECT_EQ(errorOf("gravity: [0, -9.81]\n"),
            "sim.yaml:10:10: gravity: expected a list of 3 numbers, got a list of 2");
  EXPECT_EQ(errorOf("gravity: [0, 0, -200]\n"),
            "sim.yaml:10:17: gravity[2]: -200 is out of range [-100, 100]");
  EXPECT_EQ(errorOf("imu: 3\n"),
            "sim.yaml:10:6: imu: is a section: expected a map of its keys, got '3'");
  EXPECT_EQ(errorOf("initial_joints: {left_knee: 9}\n"),
            "sim.yaml:10:29: initial_joints.left_knee: 9 is out of range [-6.28319, 6.28319]");
  EXPECT_EQ(errorOf("lidar: {vertical_min: 0.5, vertical_max: 0.1}\n"),
            "sim.yaml:10:28: lidar.vertical_max: is below lidar.vertical_min (0.5)");
  EXPECT_EQ(errorOf("- 1\n- 2\n"),
            "sim.yaml:10:1: the simbody backend section must be a map of keys");
  EXPECT_EQ(errorOf("friction: [1\n"),
            "sim.yaml:11:1: end of sequence flow not found");  // yaml-cpp's own words
  EXPECT_EQ(errorOf("friction: x\n", ""), "<backend section>:1:11: friction: expected a number, got 'x'");
}

TEST(SimSettings, EveryDefaultObeysItsOwnBounds) {
  // parseSimSettings parses the defaults through the same checks; a bad default would throw.
  EXPECT_NO_THROW(parseSimSettings("", ""));
  for (const SettingKey& key : simSettingKeys()) {
    EXPECT_NE(std::string(key.doc), "") << key.name;
    EXPECT_NE(std::string(key.defaultYaml), "") << key.name;
  }
}

// The schema round-trips: every key written at its default (the table's YAML, as
// `ballastd --dump-schema=yaml` writes the profile's) reads back as a section, each key taken
// from the text, into the settings of an empty section.
TEST(SimSettings, EveryKeyAtItsDefaultReadsBackAsASection) {
  std::vector<const schema::Key*> keys;
  for (const SettingKey& key : simSettingKeys()) keys.push_back(&key);
  const std::string yaml = schema::yamlDefaults(keys);
  SimSettings dumped;
  try {
    dumped = parseSimSettings(yaml, "dump.yaml:1");
  } catch (const SettingsError& e) {
    FAIL() << e.what() << "\n" << yaml;
  }
  const SimSettings empty = parseSimSettings("", "sim.yaml:1");
  for (const SettingKey& key : simSettingKeys()) {
    EXPECT_EQ(dumped.location.count(key.name), 1u) << key.name << " is not in the dump";
    if (key.type == schema::Type::kNumber || key.type == schema::Type::kInteger ||
        key.type == schema::Type::kBool) {
      EXPECT_EQ(std::memcmp(key.field(dumped), key.field(empty), key.size), 0) << key.name;
    }
  }
  EXPECT_EQ(dumped.gravity, empty.gravity);
  EXPECT_EQ(dumped.integrator, empty.integrator);
  EXPECT_EQ(dumped.initial_joints, empty.initial_joints);
}

}  // namespace
}  // namespace ballast::simbody
