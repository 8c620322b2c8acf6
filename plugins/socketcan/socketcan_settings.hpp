// The socketcan backend's profile section: every key declared once in a table
// (socketcanSettingKeys(), socketcan_settings.cpp) with type, default, bounds and doc, parsed by
// the schema engine the daemon's profile uses (plugins/common/settings_schema.hpp): errors read `file:line:column: key: what is wrong`.
//
// Example (the humanoid on two buses; every key but motors has a default):
//
//   buses: [can0, can1]
//   reply_timeout: 0.003
//   log: /var/log/ballast/can.log
//   imu: {bus: can0, id: 0x100}
//   ranges: {position: 12.5, velocity: 30, kp: 500, kd: 10}   # defaults for every motor
//   motors:
//     left_hip_yaw: {bus: can0, id: 1}
//     left_knee: {bus: can0, id: 4, torque: 300, direction: -1, offset: 0.1}
//     waist_yaw: {bus: can1, id: 9, hold_kp: 200, hold_kd: 4}   # in robot.locked_joints
//     ...
//
// Every key with its type, default, bounds and meaning: ballast-profile(5), section
// backend.socketcan, generated from the table (`ballastd --dump-schema=man`).
//
// A motor's joint angle is q = offset + direction · p, with p the motor's position; velocity and
// torque follow the direction. The ranges must be the motor firmware's own (P_MAX, V_MAX,
// T_MAX, KP_MAX, KD_MAX): a wrong span scales every command and reading by its ratio. Commands
// are clamped to them before packing, and the torque to the joint's URDF effort limit too.
//
// A joint the profile locks (robot.locked_joints, Config::joints[].locked) is no joint of the
// controller's, but its motor, if it has one, holds it at the locked angle with the motor's own
// PD: hold_kp, hold_kd (per motor, or hold.kp and hold.kd for all), no feed-forward, every tick,
// in every mode. The target moves from where the joint is at the first tick to the locked angle
// over hold.ramp seconds.
//
// Bus time: a tick sends every motor an 8-byte command and gets a 6-byte reply (111 + 95 bits
// on classic CAN, without bit stuffing), and the IMU's bus carries its three 8-byte frames; at
// 1 Mbit/s and 1 kHz that is at most 3 motors on a bus at 80 % load (4 without the IMU).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "mit_protocol.hpp"
#include "settings_schema.hpp"

namespace ballast::socketcan {

using schema::SettingsError;

struct MotorEntry {
  std::string joint;
  std::string bus;
  int busIndex = 0;  ///< into SocketcanSettings::buses
  int id = 0;
  MotorRanges ranges;
  double direction = 1.0;
  double offset = 0.0;
  /// A locked joint's motor (robot.locked_joints) holds it with these gains; unset: hold.kp and
  /// hold.kd (0 there: none, refused for a locked joint).
  double hold_kp = 0.0, hold_kd = 0.0;
};

inline constexpr int kMaxBuses = 16;

struct SocketcanSettings : schema::Locations {
  std::vector<std::string> buses;
  double bitrate, max_bus_load;
  int host_id;
  double reply_timeout, enable_timeout, lockstep_timeout;
  bool zero_on_start, disable_on_stop;
  std::string log;
  bool imu_enabled;
  std::string imu_bus;
  int imu_id;
  double imu_timeout;
  double ranges_position, ranges_velocity, ranges_torque, ranges_kp, ranges_kd;
  double hold_kp, hold_kd, hold_ramp;
  bool fault_code;
  /// In the order given, each one's unset ranges from ranges.*.
  std::vector<MotorEntry> motors;
  int imuBusIndex = 0;
};

using SettingKey = schema::Row<SocketcanSettings>;
const std::vector<SettingKey>& socketcanSettingKeys();

/// Parses and validates the section (buses named by motors and the IMU exist, ids unique per
/// bus and not the host's or the IMU's); throws SettingsError.
SocketcanSettings parseSocketcanSettings(const std::string& yaml, const std::string& origin);

std::string socketcanSettingsReference();
/// BackendEntry::section_doc: this section's keys as man page entries or commented YAML.
const char* socketcanSettingsDoc(const char* format);

/// Refuses a section whose per-tick frames would take more than max_bus_load of a bus's time at
/// this control period (SettingsError naming the bus and its motors).
void checkBusLoad(const SocketcanSettings& settings, double period);

}  // namespace ballast::socketcan
