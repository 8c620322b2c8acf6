// The socketcan backend against emulated motors on two socketpair buses (the humanoid: legs on
// one, arms on the other): the enable and disable sequences, commands and replies through the
// MIT protocol, clamping, silent motors and IMU faults, candump logs; and the same round trip on
// vcan0 where the kernel has SocketCAN.
#include <fcntl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <chrono>
#include <thread>

#include "socketcan_backend.hpp"
#include "urdf_joints.hpp"  // plugins/common
#include "test/unit/allocation_counter.hpp"
#include "test/integration/socketcan/can_rig.hpp"

namespace ballast::socketcan::test {
namespace {

using backend::Status;

struct Rig {
  explicit Rig(bool lockstep, const std::string& extra = "",
               const std::map<std::string, std::string>& overrides = {}, bool startRobot = true)
      : buses(2) {
    section = sectionFor(buses, map, extra, overrides);
    urdf = humanoidUrdf();
    config.section_yaml = section.c_str();
    config.section_origin = "robot.yaml:20";
    config.urdf_path = urdf.c_str();
    config.period = 0.001;
    config.lockstep = lockstep;
    if (startRobot) robot = std::make_unique<KinematicRobot>(buses, map, !lockstep);
  }
  bool configureAndStart(backend::Error& error) {
    return can.configure(config, error) && can.start(error);
  }
  /// n ticks holding `commands`; the first status other than kOk, else kOk. (A late real-time
  /// tick is reported in its TickTiming, not as a status.)
  Status ticks(int n, const backend::Commands& commands) {
    for (int k = 0; k < n; ++k) {
      Status s = can.read(sensors);
      if (s == Status::kOk) s = can.write(commands);
      if (s == Status::kOk) s = can.advance();
      if (s != Status::kOk) return s;
    }
    return Status::kOk;
  }
  backend::Commands hold() const {
    backend::Commands c;
    c.num_joints = static_cast<int>(map.joints.size());
    for (int j = 0; j < c.num_joints; ++j) {
      c.joint[j].q_des = 0.1;
      c.joint[j].kp = 50;
      c.joint[j].kd = 2;
    }
    return c;
  }

  EmulatedBuses buses;
  MotorMap map;
  std::string section, urdf;
  backend::Config config;
  std::unique_ptr<KinematicRobot> robot;
  SocketcanBackend can;
  backend::Sensors sensors;
};

TEST(SocketcanBackend, EnablesEveryMotorAtStartAndDisablesThemAtStop) {
  Rig rig(/*lockstep=*/true);
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  const backend::Capabilities& caps = rig.can.capabilities();
  EXPECT_STREQ(caps.name, "socketcan");
  EXPECT_FALSE(caps.simulation);
  EXPECT_TRUE(caps.lockstep);  // emulated buses
  EXPECT_FALSE(caps.ground_truth);
  ASSERT_EQ(caps.num_joints, 24);
  EXPECT_STREQ(caps.joint_names[0], rig.map.joints[0].c_str());
  rig.robot->with([](CanEmulator& e) {
    for (const auto& m : e.motors()) {
      EXPECT_EQ(m.enables, 1) << m.id;
      EXPECT_TRUE(m.enabled);
    }
  });
  ASSERT_EQ(rig.ticks(50, rig.hold()), Status::kOk) << rig.can.lastError().message;
  rig.can.stop();
  rig.can.stop();  // idempotent
  rig.robot->stop();
  rig.robot->with([](CanEmulator& e) {
    for (const auto& m : e.motors()) {
      EXPECT_EQ(m.disables, 1) << m.id;
      EXPECT_FALSE(m.enabled);
      EXPECT_EQ(m.zeroes, 0);
      EXPECT_EQ(m.commands, 50);
    }
    EXPECT_EQ(e.strayFrames(), 0);
  });
}

TEST(SocketcanBackend, ZeroOnStartZeroesEveryMotorAfterEnablingIt) {
  Rig rig(true, "zero_on_start: true\n");
  rig.robot->with([](CanEmulator& e) {
    for (int i = 0; i < static_cast<int>(e.motors().size()); ++i) e.motor(i).position = 0.3;
  });
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(1, rig.hold()), Status::kOk);
  rig.robot->with([](CanEmulator& e) {
    for (const auto& m : e.motors()) EXPECT_EQ(m.zeroes, 1) << m.id;
  });
  // The joints read the new zero (plus what one tick of the emulator's motion moved them).
  for (int j = 0; j < rig.sensors.num_joints; ++j) EXPECT_NEAR(rig.sensors.q[j], 0.0, 0.01) << j;
}

TEST(SocketcanBackend, CommandsAndStatesCrossTheBusWithinTheirResolution) {
  // One motor mounted the other way round, with an offset: the joint sees q = 0.1 − p.
  Rig rig(true, "", {{"left_knee", "direction: -1, offset: 0.1"}});
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  const int knee = rig.robot->motorOf("left_knee"), elbow = rig.robot->motorOf("right_elbow");
  backend::Commands c = rig.hold();
  c.joint[knee] = backend::JointCommand{30.0, 0.9, 0.5, 120.0, 3.0};
  c.joint[elbow] = backend::JointCommand{-12.0, -0.4, -1.0, 40.0, 1.0};
  ASSERT_EQ(rig.ticks(1, c), Status::kOk) << rig.can.lastError().message;
  rig.robot->with([&](CanEmulator& e) {
    const MitCommand& k = e.motor(knee).command;  // the motor's side: direction −1, offset 0.1
    EXPECT_NEAR(k.position, -(0.9 - 0.1), 25.0 / 65535);
    EXPECT_NEAR(k.velocity, -0.5, 90.0 / 4095);
    EXPECT_NEAR(k.torque, -30.0, 1000.0 / 4095);  // span ±500 (twice the URDF effort)
    EXPECT_NEAR(k.kp, 120.0, 500.0 / 4095);
    EXPECT_NEAR(k.kd, 3.0, 10.0 / 4095);
    const MitCommand& w = e.motor(elbow).command;
    EXPECT_NEAR(w.position, -0.4, 25.0 / 65535);
    EXPECT_NEAR(w.torque, -12.0, 240.0 / 4095);  // span ±120
    // And back: the motors' positions as the joints read them.
    e.motor(knee).position = -0.5;
    e.motor(elbow).position = 0.25;
  });
  // The emulator moves every motor a little on each command; read what it reports.
  ASSERT_EQ(rig.can.read(rig.sensors), Status::kOk) << rig.can.lastError().message;
  double kneeMotor = 0, elbowMotor = 0;
  rig.robot->with([&](CanEmulator& e) {
    kneeMotor = e.motor(knee).position;
    elbowMotor = e.motor(elbow).position;
  });
  // (The read above carries the replies of the last tick; one more tick for the values set.)
  ASSERT_EQ(rig.can.write(c), Status::kOk);
  ASSERT_EQ(rig.can.advance(), Status::kOk);
  ASSERT_EQ(rig.can.read(rig.sensors), Status::kOk);
  rig.robot->with([&](CanEmulator& e) {
    kneeMotor = e.motor(knee).position;
    elbowMotor = e.motor(elbow).position;
  });
  EXPECT_NEAR(rig.sensors.q[knee], 0.1 - kneeMotor, 25.0 / 65535);
  EXPECT_NEAR(rig.sensors.q[elbow], elbowMotor, 25.0 / 65535);
  EXPECT_TRUE(rig.sensors.imu_valid);
  EXPECT_NEAR(rig.sensors.imu.linear_acceleration[2], 9.81, kAccelFullScale / 32767);
  EXPECT_NEAR(rig.sensors.imu.orientation[3], 1.0, 1e-4);
  EXPECT_FALSE(rig.sensors.has_truth);
  EXPECT_NEAR(rig.sensors.time, 0.002, 1e-12);  // lockstep: two ticks of 1 ms
}

TEST(SocketcanBackend, ReadWriteAndAdvanceAllocateNothing) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("ballast-can-alloc-" + std::to_string(getpid()) + ".log")).string();
  Rig rig(true, "log: " + log + "\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  const backend::Commands c = rig.hold();
  ASSERT_EQ(rig.ticks(5, c), Status::kOk);
  Status s = Status::kOk;
  EXPECT_EQ(ballast::test::allocationsIn([&] { s = rig.ticks(200, c); }), 0);
  EXPECT_EQ(s, Status::kOk);
  rig.can.stop();
  std::filesystem::remove(log);
}

TEST(SocketcanBackend, CommandsBeyondAMotorsRangesAreClampedAndCounted) {
  Rig rig(true);
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  const int wrist = rig.robot->motorOf("left_wrist_yaw");  // effort 15 N·m, span ±30
  backend::Commands c = rig.hold();
  c.joint[wrist].tau_ff = 40.0;
  c.joint[wrist].kd = 50.0;  // ranges.kd is 10
  ASSERT_EQ(rig.ticks(1, c), Status::kOk);
  EXPECT_EQ(rig.can.clampedValues(), 2u);
  rig.robot->with([&](CanEmulator& e) {
    EXPECT_NEAR(e.motor(wrist).command.torque, 15.0, 60.0 / 4095);  // the URDF effort
    EXPECT_DOUBLE_EQ(e.motor(wrist).command.kd, 10.0);
  });
}

TEST(SocketcanBackend, ASilentMotorIsAFaultThatNamesIt) {
  // Real time: the emulator answers each command at once; one motor falls silent. (The
  // timeouts, the IMU's too, leave room for a loaded test machine.)
  Rig rig(/*lockstep=*/false, "reply_timeout: 0.05\nimu: {timeout: 0.05}\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  EXPECT_FALSE(rig.can.capabilities().simulation);
  const backend::Commands c = rig.hold();
  const int knee = rig.robot->motorOf("left_knee");
  int commandsBefore = 0;
  rig.robot->with([&](CanEmulator& e) { commandsBefore = e.motor(knee).commands; });
  ASSERT_EQ(rig.ticks(20, c), Status::kOk) << rig.can.lastError().message;
  // The knee falls silent once it has answered the last of the 20 commands (one a tick): on a
  // loaded machine the emulator lags, and a knee silenced with commands unanswered has its last
  // reply older than the last read, whose time is the test's reference below.
  bool answered = false;
  for (int i = 0; i < 5000 && !answered; ++i) {
    rig.robot->with([&](CanEmulator& e) {
      const auto& m = e.motor(knee);
      answered = m.commands == commandsBefore + 20 && !m.commanded;
      if (answered) e.motor(knee).silent = true;
    });
    if (!answered) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(answered) << "the emulator did not answer the knee's 20 commands in 5 s";
  const double silentFrom = rig.sensors.time;  // its answer is read after this
  Status s = Status::kOk;
  for (int k = 0; k < 500 && s == Status::kOk; ++k) s = rig.ticks(1, c);
  EXPECT_EQ(s, Status::kFault);
  EXPECT_GE(rig.sensors.time - silentFrom, 0.05 - 0.002);  // not before its timeout
  const std::string message = rig.can.lastError().message;
  EXPECT_NE(message.find("left_knee (" + rig.buses.spec(0) + " id 4)"), std::string::npos) << message;
  EXPECT_NE(message.find("reply_timeout"), std::string::npos) << message;
  // Faulted stays faulted.
  EXPECT_EQ(rig.can.read(rig.sensors), Status::kFault);
}

TEST(SocketcanBackend, AfterAFaultTheDaemonsDampingStillReachesTheMotors) {
  Rig rig(/*lockstep=*/false, "reply_timeout: 0.05\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(10, rig.hold()), Status::kOk) << rig.can.lastError().message;
  rig.robot->with([&](CanEmulator& e) { e.motor(rig.robot->motorOf("left_knee")).silent = true; });
  Status s = Status::kOk;
  for (int k = 0; k < 500 && s == Status::kOk; ++k) s = rig.ticks(1, rig.hold());
  ASSERT_EQ(s, Status::kFault);
  // The daemon damps: kd only, no stiffness, no torque. The other motors must get it.
  backend::Commands damp;
  damp.num_joints = static_cast<int>(rig.map.joints.size());
  for (int j = 0; j < damp.num_joints; ++j) damp.joint[j].kd = 3.0;
  EXPECT_EQ(rig.can.read(rig.sensors), Status::kFault);  // still silent: still reported
  EXPECT_EQ(rig.can.write(damp), Status::kOk);
  rig.can.advance();
  for (int tries = 0; tries < 200; ++tries) {
    bool damped = true;
    rig.robot->with([&](CanEmulator& e) {
      for (const auto& m : e.motors())
        if (!m.silent) damped = damped && m.command.kp == 0.0 && std::abs(m.command.kd - 3.0) < 0.01;
    });
    if (damped) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  rig.robot->with([&](CanEmulator& e) {
    for (const auto& m : e.motors()) {
      if (m.silent) continue;
      EXPECT_EQ(m.command.kp, 0.0) << m.id;
      EXPECT_NEAR(m.command.kd, 3.0, 10.0 / 4095) << m.id;
      EXPECT_NEAR(m.command.torque, 0.0, 2 * m.ranges.torque / 4095) << m.id;  // one step
    }
  });
}

TEST(SocketcanBackend, TheRunsClockStartsAtTheFirstTickNotAtStart) {
  // ballastd builds its planner and loop between start() and the first tick; MIT motors answer
  // only when commanded: the first read must not find them silent.
  Rig rig(/*lockstep=*/false, "reply_timeout: 0.003\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(rig.can.read(rig.sensors), Status::kOk) << rig.can.lastError().message;
  EXPECT_LT(rig.sensors.time, 0.003);
}

TEST(SocketcanBackend, AnEmulatedBusIsADuplicateTheCallerKeeps) {
  int sv[2];
  ASSERT_EQ(socketpair(AF_UNIX, SOCK_SEQPACKET, 0, sv), 0);
  {
    CanBus bus;
    std::string error;
    ASSERT_TRUE(bus.open("fd:" + std::to_string(sv[0]), error)) << error;
    EXPECT_NE(bus.fd(), sv[0]);
  }
  EXPECT_EQ(fcntl(sv[0], F_GETFD), 0);  // still open, still ours
  close(sv[0]);
  close(sv[1]);
}

TEST(SocketcanBackend, LockstepWaitsForEveryReplyAndNamesTheMissingOnes) {
  Rig rig(true, "lockstep_timeout: 0.05\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(10, rig.hold()), Status::kOk);
  rig.robot->with([&](CanEmulator& e) { e.motor(rig.robot->motorOf("right_hip_roll")).silent = true; });
  EXPECT_EQ(rig.ticks(1, rig.hold()), Status::kFault);
  const std::string message = rig.can.lastError().message;
  EXPECT_NE(message.find("right_hip_roll (" + rig.buses.spec(0) + " id 8)"), std::string::npos)
      << message;
  EXPECT_NE(message.find("lockstep_timeout"), std::string::npos) << message;
}

TEST(SocketcanBackend, StartNamesTheMotorsThatDoNotAnswer) {
  Rig rig(true, "enable_timeout: 0.05\n");
  rig.robot->with([&](CanEmulator& e) {
    e.motor(rig.robot->motorOf("left_elbow")).silent = true;
    e.motor(rig.robot->motorOf("right_ankle_roll")).silent = true;
  });
  backend::Error error;
  ASSERT_TRUE(rig.can.configure(rig.config, error)) << error.message;
  EXPECT_FALSE(rig.can.start(error));
  const std::string message = error.message;
  EXPECT_NE(message.find("no answer to the enable command"), std::string::npos) << message;
  EXPECT_NE(message.find("right_ankle_roll (" + rig.buses.spec(0) + " id 12)"), std::string::npos)
      << message;
  EXPECT_NE(message.find("left_elbow (" + rig.buses.spec(1) + " id 4)"), std::string::npos) << message;
  EXPECT_NE(message.find("check power, wiring"), std::string::npos);
  // The ones that did answer are disabled again (once the emulator has read the commands).
  int stillEnabled = 0;
  for (int tries = 0; tries < 200; ++tries) {
    stillEnabled = 0;
    rig.robot->with([&](CanEmulator& e) {
      for (const auto& m : e.motors()) stillEnabled += m.enabled && !m.silent;
    });
    if (stillEnabled == 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(stillEnabled, 0);
}

TEST(SocketcanBackend, AnImuThatStopsSendingIsAFault) {
  Rig rig(false, "imu: {timeout: 0.05}\nreply_timeout: 0.2\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(5, rig.hold()), Status::kOk) << rig.can.lastError().message;
  rig.robot->silenceImu();  // the motors go on answering
  Status s = Status::kOk;
  for (int k = 0; k < 500 && s == Status::kOk; ++k) s = rig.ticks(1, rig.hold());
  EXPECT_EQ(s, Status::kFault);
  const std::string message = rig.can.lastError().message;
  EXPECT_NE(message.find("the IMU (" + rig.buses.spec(0) + " id 256) sent no sample"),
            std::string::npos)
      << message;
}

TEST(SocketcanBackend, EveryFrameGoesToTheCandumpLog) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("ballast-can-" + std::to_string(getpid()) + ".log")).string();
  Rig rig(true, "log: " + log + "\n");
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(10, rig.hold()), Status::kOk);
  rig.can.stop();
  std::ifstream in(log);
  const std::regex line(R"(\(\d+\.\d{6}\) fd:\d+ ([0-9A-F]{3})#((?:[0-9A-F]{2})*))");
  int enables = 0, disables = 0, commands = 0, replies = 0, imu = 0;
  for (std::string l; std::getline(in, l);) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(l, m, line)) << l;
    const std::string id = m[1], data = m[2];
    if (id == "000") ++replies;
    else if (id >= "100" && id <= "102") ++imu;
    else if (data == "FFFFFFFFFFFFFFFC") ++enables;
    else if (data == "FFFFFFFFFFFFFFFD") ++disables;
    else if (data.size() == 16) ++commands;
    else ADD_FAILURE() << "unexpected frame: " << l;
  }
  EXPECT_EQ(enables, 24);
  EXPECT_EQ(commands, 24 * 10);
  EXPECT_EQ(disables, 24);
  EXPECT_GE(replies, 24 * 11);  // the enables' and 10 ticks' (the disables' may come after)
  EXPECT_GE(imu, 3 * 10);
  EXPECT_EQ(rig.can.settings().log, log);
  std::filesystem::remove(log);
}

// ballastd --check: the section against the URDF as configure() would, without opening a bus
// (a check on a laptop names no missing can0).
TEST(SocketcanBackend, CheckFindsWhatConfigureWouldWithoutOpeningTheBuses) {
  const std::string urdf = humanoidUrdf();
  backend::Config config;
  config.section_origin = "robot.yaml:10";
  config.urdf_path = urdf.c_str();
  backend::Error e;
  // Three motors a bus keep each under the bus load limit at 1 kHz.
  std::string section =
      "buses: [nocan0, nocan1, nocan2, nocan3, nocan4, nocan5, nocan6, nocan7]\nimu: {enabled: false}\n"
      "ranges: {torque: 100}\nmotors:\n";
  const char* joints[] = {"left_hip_yaw", "left_hip_roll", "left_hip_pitch", "left_knee",
                          "left_ankle_pitch", "left_ankle_roll", "right_hip_yaw", "right_hip_roll",
                          "right_hip_pitch", "right_knee", "right_ankle_pitch", "right_ankle_roll",
                          "left_shoulder_pitch", "left_shoulder_roll", "left_shoulder_yaw",
                          "left_elbow", "left_wrist_yaw", "left_wrist_pitch",
                          "right_shoulder_pitch", "right_shoulder_roll", "right_shoulder_yaw",
                          "right_elbow", "right_wrist_yaw", "right_wrist_pitch"};
  int id = 0;
  for (const char* j : joints) {
    section += std::string("  ") + j + ": {bus: nocan" + std::to_string(id % 8) +
               ", id: " + std::to_string(id / 8 + 1) + "}\n";
    ++id;
  }
  config.section_yaml = section.c_str();
  EXPECT_TRUE(SocketcanBackend::check(config, e)) << e.message;
  SocketcanBackend can;
  EXPECT_FALSE(can.configure(config, e));  // no interface nocan0 here
  const std::string missing = section.substr(0, section.rfind("  right_wrist_pitch"));
  config.section_yaml = missing.c_str();
  EXPECT_FALSE(SocketcanBackend::check(config, e));
  EXPECT_NE(std::string(e.message).find("joint right_wrist_pitch of " + urdf + " has no motor"),
            std::string::npos)
      << e.message;
}

TEST(SocketcanBackend, ALockedJointNeedsNoMotorAndItsMotorNeedsHoldGainsThatFit) {
  // The model holds the wrist yaws (the profile's locks): the section may give motors to the
  // other 22 joints only; a motor on a locked joint needs hold gains within its fields and the
  // locked angle within its position field.
  const std::string urdf = humanoidUrdf();
  backend::Config config;
  config.section_origin = "robot.yaml:10";
  config.urdf_path = urdf.c_str();
  std::vector<backend::JointModel> models(2);
  models[0].name = "left_wrist_yaw";
  models[1].name = "right_wrist_yaw";
  for (backend::JointModel& m : models) m.locked = true, m.locked_position = 0.4;
  config.joints = models.data();
  config.num_joint_models = 2;
  std::string section =
      "buses: [nocan0, nocan1, nocan2, nocan3, nocan4, nocan5, nocan6, nocan7]\nimu: {enabled: false}\n"
      "ranges: {torque: 100}\nmotors:\n";
  int id = 0;
  for (const plugin::UrdfJoint& j : plugin::urdfJoints(urdf)) {
    if (!j.movable || j.name == "left_wrist_yaw" || j.name == "right_wrist_yaw") continue;
    section += "  " + j.name + ": {bus: nocan" + std::to_string(id % 8) + ", id: " +
               std::to_string(id / 8 + 1) + "}\n";
    ++id;
  }
  ASSERT_EQ(id, 22);
  auto checked = [&](const std::string& yaml) {
    config.section_yaml = yaml.c_str();
    backend::Error e;
    return SocketcanBackend::check(config, e) ? std::string() : std::string(e.message);
  };
  EXPECT_EQ(checked(section), "");
  // Without gains: refused at its entry, saying what to give.
  EXPECT_EQ(checked(section + "  left_wrist_yaw: {bus: nocan7, id: 9}\n"),
            "robot.yaml:36:3: motors.left_wrist_yaw: joint left_wrist_yaw is locked at 0.4 rad "
            "(robot.locked_joints) and this motor holds it there: give it hold_kp and hold_kd (or "
            "hold.kp and hold.kd for every locked joint's motor), or leave its motor out of motors "
            "to leave it unpowered");
  const std::string held = section + "  left_wrist_yaw: {bus: nocan7, id: 9, hold_kp: 30, hold_kd: 1}\n";
  EXPECT_EQ(checked(held), "");
  EXPECT_EQ(checked(section + "  left_wrist_yaw: {bus: nocan7, id: 9, hold_kd: 1}\nhold: {kp: 30}\n"), "");
  EXPECT_EQ(checked(section + "  left_wrist_yaw: {bus: nocan7, id: 9, hold_kp: 30}\n"),
            "robot.yaml:36:3: motors.left_wrist_yaw: joint left_wrist_yaw is locked at 0.4 rad "
            "(robot.locked_joints) and this motor holds it there: give it hold_kd (or hold.kp and "
            "hold.kd for every locked joint's motor), or leave its motor out of motors to leave it "
            "unpowered");
  // Gains the fields cannot carry, an angle beyond the position field: refused, not clamped.
  EXPECT_EQ(checked(section + "  left_wrist_yaw: {bus: nocan7, id: 9, hold_kp: 600, hold_kd: 1}\n"),
            "robot.yaml:36:49: motors.left_wrist_yaw.hold_kp: 600 is beyond motor left_wrist_yaw's "
            "kp field (500)");
  EXPECT_NE(checked("hold: {kp: 30, kd: 20}\n" + section + "  left_wrist_yaw: {bus: nocan7, id: 9}\n")
                .find("robot.yaml:10:16: hold.kd: 20 is beyond motor left_wrist_yaw's kd field (5)"),
            std::string::npos);
  EXPECT_NE(checked(section + "  left_wrist_yaw: {bus: nocan7, id: 9, hold_kp: 30, hold_kd: 1, "
                              "position: 0.3}\n")
                .find("motors.left_wrist_yaw: joint left_wrist_yaw is locked at 0.4 rad, motor "
                      "position 0.4 rad, beyond its position field (±0.3)"),
            std::string::npos);
}

/// The rig with both wrist yaws locked (left at 0.3, right at -0.2 through a motor mounted the
/// other way round with an offset) and held by their motors.
struct LockedWristsRig : Rig {
  LockedWristsRig()
      : Rig(/*lockstep=*/true, "hold: {kp: 40, kd: 1.5, ramp: 0.05}\n",
            {{"right_wrist_yaw", "direction: -1, offset: 0.1"}}) {
    models[0].name = "left_wrist_yaw";
    models[0].locked_position = 0.3;
    models[1].name = "right_wrist_yaw";
    models[1].locked_position = -0.2;
    for (backend::JointModel& m : models) m.locked = true;
    config.joints = models.data();
    config.num_joint_models = 2;
  }
  backend::Commands commands(double q, double kp, double kd) const {
    backend::Commands c;
    c.num_joints = 22;
    for (int j = 0; j < c.num_joints; ++j) c.joint[j].q_des = q, c.joint[j].kp = kp, c.joint[j].kd = kd;
    return c;
  }
  /// The last command each motor got, by joint.
  std::map<std::string, MitCommand> lastCommands() {
    std::map<std::string, MitCommand> out;
    robot->with([&](CanEmulator& e) {
      for (const std::string& j : map.joints) out[j] = e.motor(robot->motorOf(j)).command;
    });
    return out;
  }
  std::vector<backend::JointModel> models = std::vector<backend::JointModel>(2);
};

TEST(SocketcanBackend, ALockedJointsMotorHoldsItAtItsAngleWhateverTheControllerCommands) {
  LockedWristsRig rig;
  rig.robot->with([&](CanEmulator& e) {  // every joint somewhere of its own
    for (std::size_t j = 0; j < rig.map.joints.size(); ++j) e.motor(static_cast<int>(j)).position = 0.01 * j;
  });
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  // The robot's joints are the other 22, in URDF order; they read their own motors.
  const backend::Capabilities& caps = rig.can.capabilities();
  ASSERT_EQ(caps.num_joints, 22);
  std::vector<std::string> names;
  for (int j = 0; j < caps.num_joints; ++j) names.push_back(caps.joint_names[j]);
  std::vector<std::string> expected;
  for (const std::string& j : rig.map.joints)
    if (j != "left_wrist_yaw" && j != "right_wrist_yaw") expected.push_back(j);
  EXPECT_EQ(names, expected);
  ASSERT_EQ(rig.can.read(rig.sensors), Status::kOk);
  ASSERT_EQ(rig.sensors.num_joints, 22);
  for (int j = 0; j < 22; ++j)
    EXPECT_NEAR(rig.sensors.q[j], 0.01 * rig.robot->motorOf(names[j]), 1e-3) << names[j];
  // The first hold is where the joint is (no jump), then the target ramps to the locked angle.
  const backend::Commands controller = rig.commands(0.1, 50, 2);
  ASSERT_EQ(rig.can.write(controller), Status::kOk);
  ASSERT_EQ(rig.can.advance(), Status::kOk);
  const double leftFrom = 0.01 * rig.robot->motorOf("left_wrist_yaw");
  const double step = 25.0 / 65535;  // the position field's resolution
  EXPECT_NEAR(rig.lastCommands()["left_wrist_yaw"].position, leftFrom, 2 * step);
  ASSERT_EQ(rig.ticks(24, controller), Status::kOk) << rig.can.lastError().message;
  EXPECT_NEAR(rig.lastCommands()["left_wrist_yaw"].position, leftFrom + 0.5 * (0.3 - leftFrom), 0.02);
  Status ticked = Status::kOk;  // holding allocates nothing either
  EXPECT_EQ(ballast::test::allocationsIn([&] { ticked = rig.ticks(100, controller); }), 0);
  ASSERT_EQ(ticked, Status::kOk) << rig.can.lastError().message;
  auto expectHeld = [&](const std::map<std::string, MitCommand>& c, double kp) {
    EXPECT_NEAR(c.at("left_wrist_yaw").position, 0.3, 2 * step);
    EXPECT_NEAR(c.at("right_wrist_yaw").position, 0.3, 2 * step);  // -1 · (-0.2 - 0.1)
    for (const char* j : {"left_wrist_yaw", "right_wrist_yaw"}) {
      EXPECT_NEAR(c.at(j).kp, kp, 500.0 / 4095) << j;
      EXPECT_NEAR(c.at(j).kd, 1.5, 10.0 / 4095) << j;
      EXPECT_NEAR(c.at(j).velocity, 0.0, 90.0 / 4095) << j;
      EXPECT_NEAR(c.at(j).torque, 0.0, 2 * 30.0 / 4095) << j;  // their span is 30 N·m
    }
  };
  std::map<std::string, MitCommand> c = rig.lastCommands();
  expectHeld(c, 40);
  for (const std::string& j : expected) {  // the controller's joints got its commands
    EXPECT_NEAR(c.at(j).position, 0.1, 2 * step) << j;
    EXPECT_NEAR(c.at(j).kp, 50, 500.0 / 4095) << j;
    EXPECT_NEAR(c.at(j).kd, 2, 10.0 / 4095) << j;
  }
  // The daemon damps (kd only): the locked joints stay held.
  ASSERT_EQ(rig.ticks(3, rig.commands(0.0, 0.0, 3.0)), Status::kOk);
  c = rig.lastCommands();
  expectHeld(c, 40);
  for (const std::string& j : expected) EXPECT_EQ(c.at(j).kp, 0.0) << j;
  rig.can.stop();
  rig.robot->stop();
  rig.robot->with([](CanEmulator& e) {
    for (const auto& m : e.motors()) EXPECT_EQ(m.disables, 1) << m.id;  // held ones too
  });
}

TEST(SocketcanBackend, AMotorReportingAFaultIsAFaultThatNamesItAndAFaultyHoldIsDamped) {
  LockedWristsRig rig;
  backend::Error error;
  ASSERT_TRUE(rig.configureAndStart(error)) << error.message;
  ASSERT_EQ(rig.ticks(10, rig.commands(0.1, 50, 2)), Status::kOk) << rig.can.lastError().message;
  rig.robot->with([&](CanEmulator& e) { e.motor(rig.robot->motorOf("left_wrist_yaw")).fault = 3; });
  Status s = Status::kOk;
  for (int k = 0; k < 5 && s == Status::kOk; ++k) s = rig.ticks(1, rig.commands(0.1, 50, 2));
  ASSERT_EQ(s, Status::kFault);
  const int id = rig.map.at.at("left_wrist_yaw").second;
  EXPECT_EQ(std::string(rig.can.lastError().message),
            "socketcan: motor left_wrist_yaw (" + rig.buses.spec(1) + " id " + std::to_string(id) +
                ") reports fault code 3 (the driver's; see its manual); it holds the locked "
                "joint, and is damped now");
  // The daemon damps the rest; the faulty motor's hold is damped too, the healthy one holds.
  EXPECT_EQ(rig.can.write(rig.commands(0.0, 0.0, 3.0)), Status::kOk);
  rig.can.advance();
  const std::map<std::string, MitCommand> c = rig.lastCommands();
  EXPECT_EQ(c.at("left_wrist_yaw").kp, 0.0);
  EXPECT_NEAR(c.at("left_wrist_yaw").kd, 1.5, 10.0 / 4095);
  EXPECT_NEAR(c.at("right_wrist_yaw").kp, 40, 500.0 / 4095);
  // A controlled joint's motor is named the same way; a fault from the start stops start().
  LockedWristsRig other;
  other.robot->with([&](CanEmulator& e) { e.motor(other.robot->motorOf("left_knee")).fault = 1; });
  EXPECT_FALSE(other.configureAndStart(error));
  EXPECT_EQ(std::string(error.message),
            "socketcan: motors report a fault code when enabled (the driver's; see its manual): "
            "left_knee (" + other.buses.spec(0) + " id 4)");
  // fault_code: false reads 8-byte replies as 6-byte ones.
  LockedWristsRig ignoring;
  const std::string section = ignoring.section + "fault_code: false\n";
  ignoring.config.section_yaml = section.c_str();
  ignoring.robot->with([&](CanEmulator& e) { e.motor(ignoring.robot->motorOf("left_knee")).fault = 1; });
  ASSERT_TRUE(ignoring.configureAndStart(error)) << error.message;
  EXPECT_EQ(ignoring.ticks(5, ignoring.commands(0.1, 50, 2)), Status::kOk);
}

TEST(SocketcanBackend, ARealBusOnThisMachine) {
  // On a kernel with SocketCAN and a vcan0 (`ip link add vcan0 type vcan`), an emulated motor
  // sits on vcan0 beside the backend and answers its enable sequence; elsewhere the error says
  // what is missing.
  CanBus bus;
  std::string error;
  if (!bus.open("vcan0", error)) {
    const bool noSocketCan = error.find("cannot open a CAN socket") != std::string::npos;
    EXPECT_TRUE(noSocketCan || error.find("no such CAN interface") != std::string::npos) << error;
    if (noSocketCan) {
      EXPECT_NE(error.find("load the can and can_raw modules"), std::string::npos) << error;
    }
    GTEST_SKIP() << "no vcan0 here: " << error;
  }
  const std::string urdf = (std::filesystem::temp_directory_path() /
                            ("ballast-one-joint-" + std::to_string(getpid()) + ".urdf")).string();
  std::ofstream(urdf) << R"(<robot name="one"><link name="a"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="b"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0"
    ixz="0" iyz="0"/></inertial></link><joint name="j1" type="revolute"><parent link="a"/>
    <child link="b"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="20" velocity="5"/>
    </joint></robot>)";
  CanEmulator emu;
  const int b = emu.addBus(bus.fd());
  MotorRanges r;
  r.torque = 20;
  emu.addMotor(b, 4, r);
  SocketcanBackend can;
  const std::string section = "buses: [vcan0]\nimu: {enabled: false}\nmotors:\n  j1: {bus: vcan0, id: 4}\n";
  backend::Config config;
  config.section_yaml = section.c_str();
  config.section_origin = "vcan.yaml:1";
  config.urdf_path = urdf.c_str();
  backend::Error e;
  ASSERT_TRUE(can.configure(config, e)) << e.message;
  std::atomic<bool> done{false};
  std::thread answer([&] { while (!done) emu.pump(5); });
  EXPECT_TRUE(can.start(e)) << e.message;
  can.stop();
  done = true;
  answer.join();
  EXPECT_EQ(emu.motors()[0].enables, 1);
  EXPECT_EQ(emu.motors()[0].disables, 1);
  std::filesystem::remove(urdf);
}

}  // namespace
}  // namespace ballast::socketcan::test
