// Motors and an IMU that speak the socketcan backend's protocols on emulated buses (the far end
// of a socketpair per bus): what the backend's tests talk to, and how a simulated robot plays
// the motors behind the CAN path.
//
// An emulated MIT motor answers each enable, disable and zero command with its state at once,
// and keeps the last motion command for whoever moves it (a test's kinematic model, or a
// simulation) to read; replyAll() then sends every commanded motor's state. Faults for tests:
// a motor can be silenced, and then stops answering altogether, or report a fault code. Like a device on a real bus, it
// never blocks on a full bus: a frame nobody takes is dropped.
#pragma once

#include <linux/can.h>

#include <vector>

#include "imu_protocol.hpp"
#include "mit_protocol.hpp"

namespace ballast::socketcan {

class CanEmulator {
 public:
  explicit CanEmulator(int hostId = 0) : hostId_(hostId) {}

  /// A bus: the emulator's end of it (an fd it now reads and writes; the caller keeps it open).
  int addBus(int fd);
  /// A motor on a bus; its index.
  int addMotor(int bus, int id, const MotorRanges& ranges);
  void setImu(int bus, int baseId) { imuBus_ = bus, imuBase_ = baseId; }

  /// Handles every frame waiting on the buses, waiting up to `timeoutMs` for the first.
  /// Returns the number handled.
  int pump(int timeoutMs);

  struct Motor {
    int bus = 0, id = 0;
    MotorRanges ranges;
    bool enabled = false, silent = false;
    /// Its replies: 8 bytes with this fault code when not 0 (a driver reporting a fault).
    int fault = 0;
    bool commanded = false;  ///< a motion command came since the last replyAll()
    MitCommand command;      ///< the last one
    double position = 0.0, velocity = 0.0, torque = 0.0;  ///< the motor's state (its side)
    int enables = 0, disables = 0, zeroes = 0, commands = 0;
  };
  Motor& motor(int index) { return motors_[static_cast<std::size_t>(index)]; }
  const std::vector<Motor>& motors() const { return motors_; }
  /// Every enabled, non-silent motor got a motion command since the last replyAll().
  bool allCommanded() const;
  /// Sends the state of every commanded motor (and clears `commanded`).
  void replyAll();
  void sendImu(const ImuSample& sample);
  /// Frames received that no motor or rule took.
  int strayFrames() const { return stray_; }

 private:
  void reply(Motor& m);
  int hostId_;
  std::vector<int> fds_;
  std::vector<Motor> motors_;
  int imuBus_ = -1, imuBase_ = 0x100;
  int stray_ = 0;
};

}  // namespace ballast::socketcan
