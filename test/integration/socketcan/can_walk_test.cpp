// The whole stack through the CAN path (DESIGN: the socketcan backend "end-to-end with the
// Simbody world playing the motors behind the emulated bus"): ballastd, with the socketcan
// backend on two emulated buses in lockstep, stands the simulated robot up and walks it
// through the CLI; it knows the robot only through MIT motor replies and IMU frames.
#include <gtest/gtest.h>

#include <cmath>

#include "test/integration/daemon/daemon_harness.hpp"
#include "test/integration/socketcan/can_world.hpp"

namespace ballast::socketcan::test {
namespace {

using ballast::test::Daemon;
using ballast::test::json;
using ballast::test::scratchDir;
using ballast::test::writeFile;

// sim-flat's simulated robot: its sensors as a real robot's.
constexpr const char* kSimSection =
    "friction: 0.8\ninitial_posture: stand\nencoder_resolution: 3.835e-4\n"
    "joint_velocity_noise: 0.02\ntorque_noise: 0.5\n"
    "imu: {gyro_bias: 0.005, accel_bias: 0.03, orientation_noise: 0.005}\n"
    "lidar: {enabled: false}\n";

TEST(CanPath, BallastdStandsAndWalksTheSimulatedRobotThroughCan) {
  const auto dir = scratchDir();
  EmulatedBuses buses(2);
  MotorMap map;
  CanWorld world(buses, map, kSimSection);
  const std::string log = (dir / "can.log").string();
  std::string section = sectionFor(buses, map, "log: " + log + "\n");
  // Indent the section under backend.socketcan.
  std::string indented;
  for (std::size_t at = 0, nl; at < section.size(); at = nl + 1) {
    nl = section.find('\n', at);
    indented += "    " + section.substr(at, nl - at) + "\n";
  }
  const std::string profile = writeFile(
      dir / "can.yaml", "extends: " + std::string(BALLAST_SOURCE_DIR) +
                            "/profiles/sim-flat.yaml\nbackend:\n  name: socketcan\n  socketcan:\n" +
                            indented);
  const backend::Truth start = world.truth();
  // Held (`ballast advance`): the walk starts and the robot is measured at controller times of
  // the test's, so the run is the same whatever the machine's load.
  Daemon d(dir, profile, {"--hold"});
  ASSERT_TRUE(d.running()) << d.log();
  ASSERT_EQ(d.cli({"advance", "2"}).status, 0) << d.log();
  ASSERT_EQ(d.status()["mode"], "stand") << d.status().dump() << d.log();
  EXPECT_EQ(d.status()["backend"], "socketcan");
  EXPECT_FALSE(d.status().contains("truth"));  // hardware: no ground truth
  ASSERT_EQ(d.cli({"walk", "--vx", "0.4", "--for", "4s"}).status, 0);
  ASSERT_EQ(d.cli({"advance", "+1"}).status, 0);
  ASSERT_EQ(d.status()["mode"], "walk") << d.status().dump();
  ASSERT_EQ(d.cli({"advance", "+5"}).status, 0);  // the walk's last 3 s and 2 s to settle
  ASSERT_EQ(d.status()["mode"], "stand") << d.status().dump();
  const json s = d.status();
  EXPECT_TRUE(s["faults"].empty()) << s["faults"];
  EXPECT_EQ(s["fallen"], false);
  const backend::Truth end = world.truth();
  const double walked = end.base_position[0] - start.base_position[0];
  std::printf("walked %.2f m through the CAN path (estimate %.2f m) in %ld ticks\n", walked,
              s["base"]["position"][0].get<double>(), world.ticks());
  EXPECT_GT(walked, 1.0);
  EXPECT_GT(end.base_position[2], 0.8);  // still standing, in the simulation
  EXPECT_FALSE(end.non_foot_contact);
  EXPECT_NEAR(s["base"]["position"][0].get<double>(), walked, 0.1);  // its own estimate
  EXPECT_EQ(d.stop(), 0) << d.log();
  world.stop();
  world.with([](CanEmulator& e) {
    for (const auto& m : e.motors()) {
      EXPECT_EQ(m.enables, 1) << m.id;
      EXPECT_EQ(m.disables, 1) << m.id;
    }
    EXPECT_EQ(e.strayFrames(), 0);
  });
  // The candump log has the run: the enable sequence, a command per motor per tick, the end.
  std::ifstream in(log);
  long lines = 0, enables = 0;
  for (std::string l; std::getline(in, l); ++lines)
    if (l.find("#FFFFFFFFFFFFFFFC") != std::string::npos) ++enables;
  EXPECT_EQ(enables, 24);
  EXPECT_GT(lines, 24 * 2 * world.ticks());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ballast::socketcan::test
