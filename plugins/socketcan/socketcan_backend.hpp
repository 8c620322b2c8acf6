// The SocketCAN hardware backend: the robot's motors on one or more CAN buses, spoken to in the
// MIT protocol (mit_protocol.hpp), and an IMU on a bus (imu_protocol.hpp).
//
//   configure  parse the section (socketcan_settings.hpp), read the URDF's movable joints (each
//              needs a motor entry; torque ranges default to its effort limit), open the buses
//   start      enable sequence: every motor is put in motor mode and must answer within
//              enable_timeout (asked again while silent; a list of the silent ones otherwise);
//              zero_on_start then zeroes them; the IMU must have sent a sample. The run's clock
//              and timeouts start at the first tick
//   read       drain every bus without blocking: replies update their motor, IMU frames build
//              samples; a motor or IMU silent for longer than its timeout, or a motor whose
//              reply carries a fault code, is a fault naming it (the daemon damps); a tick
//              without a new frame reuses the last ones, each younger than its timeout (one late
//              or lost frame is not a fall)
//   write      one command frame per motor, each value clamped to the motor's range (counted)
//              and the torque to the joint's URDF effort too; always sent, faulted or not (the
//              daemon's damping must reach the motors); a bus refusing frames for longer than
//              reply_timeout is a fault. The motors of locked joints get their hold (below)
//
// Locked joints (Config::joints[].locked): not the robot's joints (capabilities(), Sensors,
// Commands), but a locked joint's motor, if the section gives it one, holds it at the locked
// angle with its own PD (hold_kp, hold_kd, no feed-forward), its target ramped from where the
// joint was at the first tick over hold.ramp. It holds in every mode: the daemon's damping is
// for the joints it controls, and a joint it takes as rigid (as the simulation welds it) stays
// rigid while the robot is damped down; the hold's command depends on nothing the controller
// computes, so no controller fault can make it wrong. Only a fault of that motor (a fault code
// in its reply) turns its hold into damping (kp 0, hold_kd). Enable, disable and the reply
// timeouts cover these motors like every other.
//   advance    real time: sleep to the next deadline (lateness reported, skipped periods after a
//              stall: tick_pacer.hpp); lockstep, possible
//              only on emulated buses (fd:N): wait for every motor's reply and the IMU's sample
//   stop       disable every motor, asking the silent ones again (disable_on_stop); idempotent
//
// Joints: q = offset + direction · p (p the motor's position), velocity and torque likewise.
// Everything per tick works on arrays sized at configure: no allocation, no lock; frames go to
// the candump log through a lock-free ring.
#pragma once

#include <time.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backend_abi.hpp"
#include "can_bus.hpp"
#include "candump_log.hpp"
#include "imu_protocol.hpp"
#include "socketcan_settings.hpp"
#include "tick_pacer.hpp"  // plugins/common

namespace ballast::socketcan {

class SocketcanBackend final : public backend::Backend {
 public:
  SocketcanBackend() = default;
  ~SocketcanBackend() override { stop(); }

  bool configure(const backend::Config& config, backend::Error& error) override;
  /// What configure() checks but opening the buses (BackendEntry::check: ballastd --check).
  static bool check(const backend::Config& config, backend::Error& error);
  const backend::Capabilities& capabilities() const override { return caps_; }
  bool start(backend::Error& error) override;
  backend::Status read(backend::Sensors& sensors) override;
  backend::Status write(const backend::Commands& commands) override;
  backend::Status advance(backend::TickTiming& timing) override;
  using backend::Backend::advance;
  const backend::Error& lastError() const override { return lastError_; }
  void stop() override;

  // Diagnostics (tests).
  const SocketcanSettings& settings() const { return settings_; }
  /// Command values clamped to a motor's range since start.
  std::uint64_t clampedValues() const { return clamped_; }
  /// Frames that could not be queued for sending since start.
  std::uint64_t sendFailures() const { return sendFailures_; }

 private:
  bool configure(const backend::Config& config, backend::Error& error, bool openBuses);
  struct Motor {
    MotorEntry entry;
    double effort = 0.0;                  ///< the joint's torque limit (URDF), N·m
    double q = 0.0, dq = 0.0, tau = 0.0;  ///< joint side, from the last reply
    double lastReply = -1.0;              ///< backend clock, s; < 0: never
    bool replied = false;                 ///< since the last command
    int fault = 0;                        ///< the fault code of its last reply (0: none)
    bool held = false;                    ///< a locked joint's: holds it, commanded by nobody
    double lockedAt = 0.0;                ///< held: the locked angle (joint side)
    double holdFrom = 0.0;                ///< held: where the joint was at the first tick
  };
  struct BusState {
    const char* error = nullptr;  ///< the last error frame's class (static text)
    int sendErrno = 0;            ///< why the last send failed
    bool failedThisTick = false;
    int failingTicks = 0;         ///< consecutive ticks with a failed send
  };
  backend::Status fault(const char* message);
  /// The clock and the pacer start at the first tick (see read()).
  void beginRun();
  /// Sends `which` to every motor and waits for every answer, asking the silent ones again.
  bool sequence(MitSpecial which, double timeout);
  /// "; bus can0 reported bus-off" and the like, for fault messages.
  std::string busTrouble() const;
  /// Reads every waiting frame on every bus; true if any arrived.
  bool drain();
  /// Sends a frame on a bus (logged); false if it could not be queued.
  bool send(int bus, const can_frame& frame);
  /// Polls the buses until done() or `timeout` s of wall time; false on timeout.
  template <typename Done>
  bool waitUntil(Done done, double timeout);
  /// The motors for which `missing(m)` holds, as "left_knee (can0 id 4), ..." (at most 6).
  template <typename Missing>
  std::string motorList(Missing missing) const;
  double clock() const;  ///< backend time, s
  void sendToAll(MitSpecial which, bool onlySilent);

  SocketcanSettings settings_;
  backend::Capabilities caps_;
  backend::Error lastError_;
  std::vector<CanBus> buses_;
  std::vector<BusState> busState_;
  /// The robot's joints' motors in joint (URDF) order, then the locked joints' (held).
  std::vector<Motor> motors_;
  std::size_t commanded_ = 0;                         // motors_[0, commanded_): the robot's joints
  std::vector<std::array<std::int16_t, 256>> byId_;  // per bus: motor index by CAN id, -1 none
  ImuAssembler imu_;
  double lastImu_ = -1.0;
  std::uint64_t imuSamplesAtWrite_ = 0;
  CandumpLog log_;
  double period_ = 0.001;
  bool lockstep_ = false;
  bool configured_ = false, started_ = false, running_ = false;
  std::uint64_t tick_ = 0, sequence_ = 0, clamped_ = 0, sendFailures_ = 0;
  timespec start_{};
  plugin::TickPacer pacer_;
};

}  // namespace ballast::socketcan
