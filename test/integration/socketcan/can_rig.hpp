// The humanoid's motors on emulated CAN buses for the socketcan backend's tests: socketpairs
// (one end for the backend as fd:N, one for the emulator), the backend's section for them (legs
// on the first bus, arms on the second, ids from 1 on each), and an emulator thread that moves
// the motors as the fake backend moves its joints (unit inertias following their PD commands,
// no gravity) and sends a level IMU at rest.
#pragma once

#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "can_emulator.hpp"
#include "urdf_joints.hpp"

namespace ballast::socketcan::test {

inline std::string humanoidUrdf() { return std::string(BALLAST_SOURCE_DIR) + "/urdf/humanoid.urdf"; }

inline std::vector<std::string> humanoidJoints() {
  std::vector<std::string> names;
  for (const auto& j : plugin::urdfJoints(humanoidUrdf()))
    if (j.movable) names.push_back(j.name);
  return names;
}

/// Socketpairs for `n` buses: backend ends and emulator ends.
struct EmulatedBuses {
  explicit EmulatedBuses(int n) {
    for (int i = 0; i < n; ++i) {
      int sv[2];
      if (socketpair(AF_UNIX, SOCK_SEQPACKET, 0, sv) == 0) {
        backend.push_back(sv[0]);
        emulator.push_back(sv[1]);
      }
    }
  }
  ~EmulatedBuses() {
    for (int fd : emulator) close(fd);
    for (int fd : backend) close(fd);  // the backend works on duplicates
  }
  std::string spec(int i) const { return "fd:" + std::to_string(backend[static_cast<std::size_t>(i)]); }
  std::vector<int> backend, emulator;
};

/// Which bus and id each joint's motor has: legs (the first 12) on bus 0, the rest on bus 1;
/// and its torque span (the emulated firmware's T_MAX): twice the joint's URDF effort.
struct MotorMap {
  std::map<std::string, std::pair<int, int>> at;  // joint -> (bus, id)
  std::map<std::string, double> torqueSpan;
  std::vector<std::string> joints;
  MotorMap() {
    for (const auto& j : plugin::urdfJoints(humanoidUrdf()))
      if (j.movable) {
        joints.push_back(j.name);
        torqueSpan[j.name] = 2.0 * j.effort;
      }
    int ids[2] = {0, 0};
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const int bus = j < 12 ? 0 : 1;
      at[joints[j]] = {bus, ++ids[bus]};
    }
  }
};

/// The backend section: buses, the IMU on bus 0, every motor, plus `extra` YAML lines; a
/// joint in `overrides` gets those keys in its entry.
inline std::string sectionFor(const EmulatedBuses& buses, const MotorMap& map,
                              const std::string& extra = "",
                              const std::map<std::string, std::string>& overrides = {}) {
  std::string y = "buses: [" + buses.spec(0) + ", " + buses.spec(1) + "]\nranges: {kd: 10}\nmotors:\n";
  for (const auto& j : map.joints) {
    const auto [bus, id] = map.at.at(j);
    y += "  " + j + ": {bus: " + buses.spec(bus) + ", id: " + std::to_string(id) +
         ", torque: " + std::to_string(map.torqueSpan.at(j));
    const auto o = overrides.find(j);
    if (o != overrides.end()) y += ", " + o->second;
    y += "}\n";
  }
  return y + extra;
}

/// The emulator with the humanoid's motors (their ranges as the backend's section gives them).
inline void addHumanoidMotors(CanEmulator& emu, const MotorMap& map) {
  for (const auto& joint : map.joints) {
    MotorRanges r;
    r.torque = map.torqueSpan.at(joint);
    r.kd = 10;
    const auto [bus, id] = map.at.at(joint);
    emu.addMotor(bus, id, r);
  }
}

/// The emulator on its own thread, playing kinematic motors and a level IMU at rest: when every
/// enabled motor has a command (or right away in real time: `immediate`) the motors move one
/// period and reply, then the IMU sends a sample.
class KinematicRobot {
 public:
  KinematicRobot(const EmulatedBuses& buses, const MotorMap& map, bool immediate,
                 double period = 0.001)
      : map_(map), immediate_(immediate), period_(period) {
    for (int fd : buses.emulator) emu_.addBus(fd);
    addHumanoidMotors(emu_, map);
    emu_.setImu(0, 0x100);
    thread_ = std::thread([this] { run(); });
  }
  ~KinematicRobot() { stop(); }
  void stop() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }
  /// Runs f on the emulator, between its steps.
  void with(const std::function<void(CanEmulator&)>& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f(emu_);
  }
  int motorOf(const std::string& joint) const {
    for (std::size_t j = 0; j < map_.joints.size(); ++j)
      if (map_.joints[j] == joint) return static_cast<int>(j);
    return -1;
  }
  int samples() const { return samples_; }
  /// The IMU stops sending (the motors go on).
  void silenceImu() { imuOn_ = false; }

 private:
  void run() {
    ImuSample imu;
    imu.linear_acceleration[2] = 9.81;
    while (!done_) {
      std::lock_guard<std::mutex> lock(mutex_);
      const int frames = emu_.pump(1);
      bool any = false;
      for (const auto& m : emu_.motors()) any = any || m.commanded;
      if (!any || (!immediate_ && !emu_.allCommanded())) {
        // The IMU talks from power-on, whatever the motors do.
        if (frames == 0 && imuOn_) {
          imu.counter = static_cast<std::uint16_t>(imu.counter + 1);
          emu_.sendImu(imu);
        }
        continue;
      }
      for (int i = 0; i < static_cast<int>(emu_.motors().size()); ++i) {
        CanEmulator::Motor& m = emu_.motor(i);
        if (!m.commanded) continue;
        const MitCommand& c = m.command;
        const double acc = c.kp * (c.position - m.position) + c.kd * (c.velocity - m.velocity);
        m.velocity = (m.velocity + acc * period_) * 0.999;
        m.position += m.velocity * period_;
        m.torque = c.torque;
      }
      emu_.replyAll();
      imu.counter = static_cast<std::uint16_t>(imu.counter + 1);
      if (imuOn_) emu_.sendImu(imu);
      ++samples_;
    }
  }

  MotorMap map_;
  CanEmulator emu_;
  bool immediate_;
  double period_;
  std::mutex mutex_;
  std::atomic<bool> done_{false}, imuOn_{true};
  std::atomic<int> samples_{0};
  std::thread thread_;
};

}  // namespace ballast::socketcan::test
