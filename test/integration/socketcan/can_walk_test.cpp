// The whole stack through the CAN path (DESIGN: the socketcan backend "end-to-end with the
// Simbody world playing the motors behind the emulated bus"): ballastd, with the socketcan
// backend on two emulated buses in lockstep, stands the simulated robot up and walks it
// through the CLI; it knows the robot only through MIT motor replies and IMU frames.
#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include "test/integration/daemon/daemon_harness.hpp"
#include "test/integration/socketcan/can_world.hpp"

namespace ballast::socketcan::test {
namespace {

using ballast::test::Daemon;
using ballast::test::json;
using ballast::test::scratchDir;
using ballast::test::writeFile;
namespace fs = std::filesystem;

// sim-flat's simulated robot: its sensors as a real robot's.
constexpr const char* kSimSection =
    "friction: 0.8\ninitial_posture: stand\nencoder_resolution: 3.835e-4\n"
    "joint_velocity_noise: 0.02\ntorque_noise: 0.5\n"
    "imu: {gyro_bias: 0.005, accel_bias: 0.03, orientation_noise: 0.005}\n"
    "lidar: {enabled: false}\n";

/// sim-flat on the socketcan backend with `section` (and `robot`, YAML under robot:).
std::string canProfile(const fs::path& dir, const std::string& section, const std::string& robot = "") {
  // Indent the section under backend.socketcan.
  std::string indented;
  for (std::size_t at = 0, nl; at < section.size(); at = nl + 1) {
    nl = section.find('\n', at);
    indented += "    " + section.substr(at, nl - at) + "\n";
  }
  return writeFile(dir / "can.yaml", "extends: " + std::string(BALLAST_SOURCE_DIR) +
                                         "/profiles/sim-flat.yaml\n" +
                                         (robot.empty() ? "" : "robot:\n" + robot) +
                                         "backend:\n  name: socketcan\n  socketcan:\n" + indented);
}

/// While it lives, the daemon is stopped (SIGSTOP) for `pause` of every `every` seconds of wall
/// time: a loaded machine that does not schedule it. The world behind the buses goes on meanwhile
/// (its thread is the test's), as its IMU would on a machine that runs it.
class Unscheduled {
 public:
  Unscheduled(Daemon& daemon, double pause, double every)
      : thread_([this, &daemon, pause, every] {
          using namespace std::chrono;
          while (!done_) {
            daemon.signal(SIGSTOP);
            std::this_thread::sleep_for(duration<double>(pause));
            daemon.signal(SIGCONT);
            std::this_thread::sleep_for(duration<double>(every - pause));
          }
        }) {}
  ~Unscheduled() {
    done_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> done_{false};
  std::thread thread_;
};

TEST(CanPath, BallastdStandsAndWalksTheSimulatedRobotThroughCan) {
  const auto dir = scratchDir();
  EmulatedBuses buses(2);
  MotorMap map;
  CanWorld world(buses, map, kSimSection);
  const std::string log = (dir / "can.log").string();
  const std::string profile = canProfile(dir, sectionFor(buses, map, "log: " + log + "\n"));
  const backend::Truth start = world.truth();
  // Held (`ballast advance`): the walk starts and the robot is measured at controller times of
  // the test's, so the run is the same whatever the machine's load.
  Daemon d(dir, profile, {"--hold"});
  ASSERT_TRUE(d.running()) << d.log();
  // Held lockstep waits for a daemon the machine does not run: the same run, however loaded.
  std::optional<Unscheduled> unscheduled(std::in_place, d, 0.3, 1.0);
  ASSERT_EQ(d.cli({"advance", "2"}).status, 0) << d.log();
  ASSERT_EQ(d.status()["mode"], "stand") << d.status().dump() << d.log();
  EXPECT_EQ(d.status()["backend"], "socketcan");
  EXPECT_FALSE(d.status().contains("truth"));  // hardware: no ground truth
  ASSERT_EQ(d.cli({"walk", "--vx", "0.4", "--for", "4s"}).status, 0);
  ASSERT_EQ(d.cli({"advance", "+1"}).status, 0);
  ASSERT_EQ(d.status()["mode"], "walk") << d.status().dump();
  ASSERT_EQ(d.cli({"advance", "+5"}).status, 0);  // the walk's last 3 s and 2 s to settle
  ASSERT_EQ(d.status()["mode"], "stand") << d.status().dump();
  unscheduled.reset();
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

// The wrist yaws locked in the profile, their motors on the bus: the controller knows 22 joints,
// and the motors hold the wrists at the locked angles in the simulation, which leaves them free
// (only the motors' PD holds them). Then a held motor reports a fault: ballastd damps, naming it.
TEST(CanPath, LockedJointsAreHeldByTheirMotorsAndAMotorFaultDampsTheRobot) {
  const auto dir = scratchDir();
  EmulatedBuses buses(2);
  MotorMap map;
  CanWorld world(buses, map, kSimSection);
  const std::string profile = canProfile(
      dir, sectionFor(buses, map, "hold: {kp: 20, kd: 0.5, ramp: 0.5}\n"),
      "  locked_joints: {left_wrist_yaw: 0.3, right_wrist_yaw: -0.3}\n"
      "  joint_groups:\n"
      "    arms: [left_shoulder_pitch, left_shoulder_roll, left_shoulder_yaw, left_elbow,\n"
      "           left_wrist_pitch, right_shoulder_pitch, right_shoulder_roll, right_shoulder_yaw,\n"
      "           right_elbow, right_wrist_pitch]\n");
  // Not held: after a backend fault the loop's clock, the backend's, stops (ballast advance
  // would wait for ever); the steps here need no particular controller time.
  Daemon d(dir, profile);
  ASSERT_TRUE(d.running()) << d.log();
  ASSERT_TRUE(d.waitFor([](const json& st) { return st["t"].get<double>() > 2.0; }, 60)) << d.log();
  json s = d.status();
  ASSERT_EQ(s["mode"], "stand") << s.dump() << d.log();
  EXPECT_TRUE(s["faults"].empty()) << s["faults"];
  const double left = world.jointPosition("left_wrist_yaw"), right = world.jointPosition("right_wrist_yaw");
  std::printf("held wrists at %.4f and %.4f rad (locked at 0.3, -0.3)\n", left, right);
  EXPECT_NEAR(left, 0.3, 0.02);
  EXPECT_NEAR(right, -0.3, 0.02);
  world.with([&](CanEmulator& e) {
    for (const auto& [joint, target] : {std::pair{"left_wrist_yaw", 0.3}, {"right_wrist_yaw", -0.3}}) {
      const auto [bus, id] = map.at.at(joint);
      for (const auto& m : e.motors())
        if (m.bus == bus && m.id == id) {
          EXPECT_NEAR(m.command.position, target, 1e-3) << joint;
          EXPECT_NEAR(m.command.kp, 20, 500.0 / 4095) << joint;
          EXPECT_NEAR(m.command.kd, 0.5, 10.0 / 4095) << joint;
          EXPECT_NEAR(m.command.torque, 0, 2 * m.ranges.torque / 4095) << joint;
        }
    }
  });
  // The left wrist's motor reports a fault code.
  world.with([&](CanEmulator& e) {
    const auto [bus, id] = map.at.at("left_wrist_yaw");
    for (int i = 0; i < static_cast<int>(e.motors().size()); ++i)
      if (e.motor(i).bus == bus && e.motor(i).id == id) e.motor(i).fault = 2;
  });
  EXPECT_TRUE(d.waitForMode("damp", 10)) << d.log();
  s = d.status();
  ASSERT_FALSE(s["faults"].empty()) << s.dump();
  EXPECT_NE(s["faults"].dump().find("motor left_wrist_yaw"), std::string::npos) << s["faults"];
  EXPECT_NE(s["faults"].dump().find("fault code 2"), std::string::npos) << s["faults"];
  EXPECT_EQ(d.stop(), 0) << d.log();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ballast::socketcan::test
