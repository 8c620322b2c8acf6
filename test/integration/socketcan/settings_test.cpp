// The socketcan backend's profile section: defaults, every kind of error with
// file:line:column, the checks across keys, and the header comment that lists every key.
#include <gtest/gtest.h>

#include <cstring>

#include "socketcan_backend.hpp"
#include "socketcan_settings.hpp"
#include "test/integration/socketcan/can_rig.hpp"

namespace ballast::socketcan {
namespace {

std::string errorOf(const std::string& yaml, const std::string& origin = "robot.yaml:10") {
  try {
    parseSocketcanSettings(yaml, origin);
  } catch (const SettingsError& e) {
    return e.what();
  }
  return "";
}

TEST(SocketcanSettings, DefaultsAndMotorEntries) {
  const SocketcanSettings s = parseSocketcanSettings(
      "buses: [can0, can1]\nranges: {kd: 10}\nmotors:\n"
      "  left_knee: {bus: can1, id: 4, torque: 300, direction: -1, offset: 0.1}\n"
      "  left_hip_yaw: {bus: can0, id: 1, torque: 18}\n",
      "robot.yaml:10");
  EXPECT_EQ(s.buses, (std::vector<std::string>{"can0", "can1"}));
  EXPECT_EQ(s.host_id, 0);
  EXPECT_DOUBLE_EQ(s.reply_timeout, 0.003);
  EXPECT_TRUE(s.imu_enabled);
  EXPECT_EQ(s.imu_id, 0x100);
  EXPECT_EQ(s.imuBusIndex, 0);
  ASSERT_EQ(s.motors.size(), 2u);
  const MotorEntry& knee = s.motors[0];
  EXPECT_EQ(knee.joint, "left_knee");
  EXPECT_EQ(knee.busIndex, 1);
  EXPECT_EQ(knee.id, 4);
  EXPECT_DOUBLE_EQ(knee.ranges.torque, 300);
  EXPECT_DOUBLE_EQ(knee.ranges.kd, 10);  // from ranges.kd
  EXPECT_DOUBLE_EQ(knee.ranges.position, 12.5);
  EXPECT_DOUBLE_EQ(knee.direction, -1);
  EXPECT_DOUBLE_EQ(knee.offset, 0.1);
  EXPECT_DOUBLE_EQ(s.motors[1].ranges.torque, 18);
  EXPECT_EQ(s.where("motors.left_knee.id"), "robot.yaml:13:30: motors.left_knee.id: ");
}

TEST(SocketcanSettings, CanIdsMayBeHexadecimal) {
  const SocketcanSettings s =
      parseSocketcanSettings("imu: {id: 0x100}\nmotors:\n  a: {bus: can0, id: 0x0A, torque: 18}\n", "r.yaml:1");
  EXPECT_EQ(s.imu_id, 256);
  EXPECT_EQ(s.motors[0].id, 10);
  EXPECT_EQ(errorOf("imu: {id: 0x1000}\n"), "robot.yaml:10:11: imu.id: 0x1000 is out of range [1, 2045]");
}

TEST(SocketcanSettings, TheShippedHardwareProfileHasAMotorForEveryJoint) {
  const YAML::Node profile =
      YAML::LoadFile(std::string(BALLAST_SOURCE_DIR) + "/profiles/hardware-example.yaml");
  YAML::Emitter out;
  out << profile["backend"]["socketcan"];
  const SocketcanSettings s = parseSocketcanSettings(out.c_str(), "hardware-example.yaml:1");
  std::vector<std::string> joints;
  for (const MotorEntry& m : s.motors) joints.push_back(m.joint);
  EXPECT_EQ(joints, test::humanoidJoints());
  EXPECT_EQ(s.buses, (std::vector<std::string>{"can0", "can1", "can2", "can3"}));
  EXPECT_EQ(s.imu_id, 0x100);
}

TEST(SocketcanSettings, ErrorsSayFileLineColumnKeyAndWhatIsWrong) {
  EXPECT_EQ(errorOf("bueses: [can0]\n"), "robot.yaml:10:1: bueses: unknown key (did you mean buses?)");
  EXPECT_EQ(errorOf("reply_timeout: 5\n"),
            "robot.yaml:10:16: reply_timeout: 5 is out of range [0.0005, 1]");
  EXPECT_EQ(errorOf("buses: can0\n"), "robot.yaml:10:8: buses: expected a list of strings, got 'can0'");
  EXPECT_EQ(errorOf("motors:\n  left_knee: {bus: can1, id: 4}\n"),
            "robot.yaml:11:20: motors.left_knee.bus: can1 is not one of buses (can0)");
  EXPECT_EQ(errorOf("ranges: {torque: 18}\nmotors:\n  a: {bus: can0, id: 4}\n  b: {bus: can0, id: 4}\n", "robot.yaml:9"),
            "robot.yaml:12:22: motors.b.id: 4 is used twice on can0");
  EXPECT_EQ(errorOf("motors:\n  a: {bus: can0, id: 0}\n"),
            "robot.yaml:11:22: motors.a.id: 0 is out of range [1, 255]");
  EXPECT_EQ(errorOf("host_id: 5\nmotors:\n  a: {bus: can0, id: 5, torque: 18}\n"),
            "robot.yaml:12:22: motors.a.id: 5 is host_id, the id replies are sent to");
  EXPECT_EQ(errorOf("imu: {id: 10}\nmotors:\n  a: {bus: can0, id: 11, torque: 18}\n"),
            "robot.yaml:12:22: motors.a.id: 11 is one of the IMU's ids (10..12)");
  EXPECT_EQ(errorOf("motors:\n  a: {bus: can0, id: 1, torqe: 5}\n"),
            "robot.yaml:11:25: motors.a.torqe: unknown key (did you mean torque?)");
  EXPECT_EQ(errorOf("motors:\n  a: {bus: can0, id: 1, direction: 0.5}\n"),
            "robot.yaml:11:36: motors.a.direction: must be 1 or -1");
  EXPECT_EQ(errorOf("motors:\n  a: {id: 1}\n"), "robot.yaml:11:3: motors.a: needs bus: (one of buses)");
  EXPECT_EQ(errorOf("buses: [can0, can0]\n"), "robot.yaml:10:1: buses: can0 is listed twice");
  EXPECT_EQ(errorOf("motors:\n  a: {bus: can0, id: 1}\n"),
            "robot.yaml:11:3: motors.a: needs torque: the span of its torque field, the firmware's "
            "T_MAX in N·m (or give ranges.torque for every motor)");
  EXPECT_EQ(errorOf("ranges: {torque: 18}\nmotors:\n  a: {bus: can0, id: 1}\n  a: {bus: can0, id: 2}\n", "robot.yaml:9"),
            "robot.yaml:12:3: motors.a: given twice");
  EXPECT_EQ(errorOf("host_id: 257\n"), "robot.yaml:10:1: host_id: 257 is one of the IMU's ids (256..258)");
  EXPECT_EQ(errorOf("buses: [a, b, c, d, e, f, g, h, i, j, k, l, m, n, o, p, q]\n"),
            "robot.yaml:10:1: buses: at most 16 buses");
  EXPECT_EQ(errorOf("imu: {bus: can9}\n"), "robot.yaml:10:7: imu.bus: can9 is not one of buses (can0)");
}

TEST(SocketcanSettings, BusLoadIsCheckedAgainstTheBitRateAndTheControlRate) {
  // Four motors and the IMU on can0 at 1 kHz: 4 × 206 + 333 bits = 115 % of 1 Mbit/s.
  std::string motors = "ranges: {torque: 18}\nmotors:\n";
  for (int i = 1; i <= 4; ++i) motors += "  m" + std::to_string(i) + ": {bus: can0, id: " + std::to_string(i) + "}\n";
  const SocketcanSettings s = parseSocketcanSettings("buses: [can0]\n" + motors, "robot.yaml:1");
  try {
    checkBusLoad(s, 0.001);
    ADD_FAILURE() << "4 motors and the IMU fit on one bus at 1 kHz?";
  } catch (const SettingsError& e) {
    EXPECT_STREQ(e.what(), "robot.yaml:1:1: buses: bus can0: 4 motors and the IMU need 1157 bits a tick, "
                           "116 % of the bus at 1000000 bit/s and 1000 Hz (max_bus_load 80 %): "
                           "spread the motors over more buses");
  }
  EXPECT_NO_THROW(checkBusLoad(s, 0.002));  // at 500 Hz it fits (58 %)
  // An emulated bus has no wire to share.
  const SocketcanSettings emulated = parseSocketcanSettings(
      "buses: [fd:3]\nranges: {torque: 18}\nmotors:\n  m1: {bus: fd:3, id: 1}\n", "robot.yaml:1");
  EXPECT_NO_THROW(checkBusLoad(emulated, 1e-5));
  // The hardware template fits at its control rate.
  const YAML::Node profile =
      YAML::LoadFile(std::string(BALLAST_SOURCE_DIR) + "/profiles/hardware-example.yaml");
  YAML::Emitter out;
  out << profile["backend"]["socketcan"];
  EXPECT_NO_THROW(checkBusLoad(parseSocketcanSettings(out.c_str(), "hw.yaml:1"),
                               1.0 / profile["control"]["rate"].as<double>()));
}

TEST(SocketcanSettings, TheBackendChecksTheSectionAgainstTheUrdf) {
  using namespace test;
  EmulatedBuses buses(2);
  MotorMap map;
  const std::string urdf = humanoidUrdf();
  auto configureWith = [&](const std::string& section) {
    SocketcanBackend can;
    backend::Config config;
    config.section_yaml = section.c_str();
    config.section_origin = "robot.yaml:20";
    config.urdf_path = urdf.c_str();
    backend::Error error;
    return can.configure(config, error) ? std::string() : std::string(error.message);
  };
  std::string section = sectionFor(buses, map);
  EXPECT_EQ(configureWith(section), "");
  // A joint without a motor.
  const std::string noKnee = section.substr(0, section.find("  left_knee:")) +
                             section.substr(section.find('\n', section.find("  left_knee:")) + 1);
  EXPECT_NE(configureWith(noKnee).find("joint left_knee of " + urdf + " has no motor"),
            std::string::npos)
      << configureWith(noKnee);
  // A motor for no joint.
  const std::string tail = configureWith(section + "  tail: {bus: " + buses.spec(0) + ", id: 99, torque: 5}\n");
  EXPECT_NE(tail.find("robot.yaml:47:3: motors.tail: " + urdf + " has no movable joint tail"),
            std::string::npos)
      << tail;
  // A bus that is not an open socket.
  std::string badBus = section;
  for (auto at = badBus.find(buses.spec(0)); at != std::string::npos; at = badBus.find(buses.spec(0)))
    badBus.replace(at, buses.spec(0).size(), "fd:999");
  const std::string closed = configureWith(badBus);
  EXPECT_NE(closed.find("bus fd:999: not an open socket"), std::string::npos) << closed;
}

// The schema round-trips: every key written at its default (the table's YAML, as
// `ballastd --dump-schema=yaml` writes the profile's) reads back as a section, each key taken
// from the text, into the settings of an empty section.
TEST(SocketcanSettings, EveryKeyAtItsDefaultReadsBackAsASection) {
  std::vector<const schema::Key*> keys;
  for (const SettingKey& key : socketcanSettingKeys()) keys.push_back(&key);
  const std::string yaml = schema::yamlDefaults(keys);
  SocketcanSettings dumped;
  try {
    dumped = parseSocketcanSettings(yaml, "dump.yaml:1");
  } catch (const SettingsError& e) {
    FAIL() << e.what() << "\n" << yaml;
  }
  const SocketcanSettings empty = parseSocketcanSettings("", "robot.yaml:1");
  for (const SettingKey& key : socketcanSettingKeys()) {
    EXPECT_EQ(dumped.location.count(key.name), 1u) << key.name << " is not in the dump";
    if (key.type == schema::Type::kNumber || key.type == schema::Type::kInteger ||
        key.type == schema::Type::kBool) {
      EXPECT_EQ(std::memcmp(key.field(dumped), key.field(empty), key.size), 0) << key.name;
    }
  }
  EXPECT_EQ(dumped.buses, empty.buses);
  EXPECT_EQ(dumped.motors.size(), empty.motors.size());
}

}  // namespace
}  // namespace ballast::socketcan
