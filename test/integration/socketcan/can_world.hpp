// The Simbody world playing the motors and the IMU behind emulated CAN buses: what ballastd's
// CAN path drives in the end-to-end test. A thread waits until every enabled motor has its
// command for the tick, hands them to the simulation (backend plugin, lockstep), steps it one
// period, and answers with the motors' new states and an IMU sample. Until the first tick (the
// backend's start waits for the IMU, the motors are enabled) the IMU sends on its own, as a real
// one does; once the world ticks, its time passes only with the ticks, and so do the IMU's
// samples: one per tick, after the step. A sample between ticks would be the state before the
// step, and could count as the tick's (the backend waits for any sample after its write), and
// while ballastd is not scheduled (a loaded machine) such samples filled the bus's socket until
// the motors' replies on it were dropped (the lockstep tick then timed out and damped).
#pragma once

#include <atomic>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "backend/plugin_loader.hpp"
#include "can_emulator.hpp"
#include "test/integration/socketcan/can_rig.hpp"
#include "test/integration/simulation_support.hpp"

namespace ballast::socketcan::test {

class CanWorld {
 public:
  CanWorld(const EmulatedBuses& buses, const MotorMap& map, const std::string& simSection)
      : map_(map) {
    plugin_ = backend::Plugin::load("simbody");
    sim_ = ballast::test::startHumanoidSimulation(*plugin_, simSection, "can_world:1", 1);
    const backend::Capabilities& caps = sim_->capabilities();
    for (int fd : buses.emulator) emu_.addBus(fd);
    addHumanoidMotors(emu_, map);
    emu_.setImu(0, 0x100);
    // Motor index (URDF order) <-> simulation joint.
    for (const auto& joint : map.joints) {
      int k = -1;
      for (int j = 0; j < caps.num_joints; ++j)
        if (joint == caps.joint_names[j]) k = j;
      simJoint_.push_back(k);
    }
    commands_.num_joints = caps.num_joints;
    sim_->read(sensors_);
    copyStateToMotors();
    thread_ = std::thread([this] { run(); });
  }
  ~CanWorld() { stop(); }
  void stop() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }

  /// The simulation's latest ground truth, and the emulator, between ticks.
  backend::Truth truth() {
    std::lock_guard<std::mutex> lock(mutex_);
    return sensors_.truth;
  }
  template <typename F>
  void with(F f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f(emu_);
  }
  long ticks() const { return ticks_; }
  /// A joint's position in the simulation (rad), between ticks.
  double jointPosition(const std::string& joint) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t i = 0; i < map_.joints.size(); ++i)
      if (map_.joints[i] == joint) return sensors_.q[simJoint_[i]];
    return std::nan("");
  }

 private:
  void copyStateToMotors() {
    for (std::size_t i = 0; i < simJoint_.size(); ++i) {
      CanEmulator::Motor& m = emu_.motor(static_cast<int>(i));
      const int k = simJoint_[i];
      m.position = sensors_.q[k];
      m.velocity = sensors_.dq[k];
      m.torque = sensors_.tau[k];
    }
  }
  void sendImu() {
    ImuSample s;
    std::copy(sensors_.imu.orientation, sensors_.imu.orientation + 4, s.orientation);
    std::copy(sensors_.imu.angular_velocity, sensors_.imu.angular_velocity + 3, s.angular_velocity);
    std::copy(sensors_.imu.linear_acceleration, sensors_.imu.linear_acceleration + 3,
              s.linear_acceleration);
    s.counter = ++imuCounter_;
    emu_.sendImu(s);
  }
  void run() {
    while (!done_) {
      std::lock_guard<std::mutex> lock(mutex_);
      const int frames = emu_.pump(1);
      bool any = false;
      for (const auto& m : emu_.motors()) any = any || m.commanded;
      if (!any || !emu_.allCommanded()) {
        if (frames == 0 && ticks_ == 0) sendImu();
        continue;
      }
      for (std::size_t i = 0; i < simJoint_.size(); ++i) {
        const CanEmulator::Motor& m = emu_.motor(static_cast<int>(i));
        backend::JointCommand& c = commands_.joint[simJoint_[i]];
        // A motor out of motor mode (disabled) applies nothing.
        c = m.enabled ? backend::JointCommand{m.command.torque, m.command.position,
                                              m.command.velocity, m.command.kp, m.command.kd}
                      : backend::JointCommand{};
      }
      if (sim_->write(commands_) != backend::Status::kOk ||
          sim_->advance() != backend::Status::kOk || sim_->read(sensors_) != backend::Status::kOk)
        return;  // the simulation failed: the motors fall silent, ballastd will say so
      copyStateToMotors();
      emu_.replyAll();
      sendImu();
      ++ticks_;
    }
  }

  MotorMap map_;
  std::shared_ptr<backend::Plugin> plugin_;
  backend::BackendPtr sim_;
  CanEmulator emu_;
  std::vector<int> simJoint_;
  backend::Commands commands_;
  backend::Sensors sensors_;
  std::uint16_t imuCounter_ = 0;
  std::mutex mutex_;
  std::atomic<bool> done_{false};
  std::atomic<long> ticks_{0};
  std::thread thread_;
};

}  // namespace ballast::socketcan::test
