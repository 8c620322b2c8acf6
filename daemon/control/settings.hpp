// What the control loop, its controllers and the planner take from a profile: a value. The
// profile layer (daemon/profile) builds it from the profile's schema, which holds every key's
// default and bounds (a default-built ControlSettings is profile::defaultSettings().control), and
// checks it against the model; nothing changes it afterwards, and threads share it as
// shared_ptr<const ControlSettings> (settings_keeper.hpp says who frees it). It owns no
// controller: the loop's controllers take their numbers from it. Per-joint arrays are in the
// model's joint order. The keys marked "restart" in the profile schema (robot, backend, rate)
// never change under a running loop.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "control/types.hpp"
#include "estimation/settings.hpp"
#include "locomotion/locomotion_planner.hpp"
#include "wbc/settings.hpp"

namespace ballast::control {

struct ControlSettings {
  std::string profile_name;  ///< for messages only
  /// The profile key of one of these settings' fields, for messages ("safety.max_vx"). The
  /// profile layer sets it (control includes no profile: it knows fields, not keys); nullptr
  /// when the settings came from elsewhere. Allocates nothing.
  const char* (*key_of)(const ControlSettings& settings, const void* field) = nullptr;

  // control
  double rate;  ///< Hz
  Mode initial_mode;
  double stand_up_duration;   ///< s
  double gain_blend_time;     ///< s, profile switch
  bool gravity_compensation;
  double pose_speed;          ///< m/s, standing height changes
  double pose_angular_speed;  ///< rad/s, standing orientation changes
  int num_joints = 0;
  std::array<double, kMaxJoints> kp{}, kd{};   ///< joint PD gains
  std::array<double, kMaxJoints> nominal_q{};  ///< nominal standing posture

  // robot
  std::array<std::string, kNumContacts> contact_frames;
  std::string imu_frame;
  /// Empty when a foot can turn about the vertical relative to the base (a hip yaw); else why
  /// neither can: such a robot cannot turn, and walk and pose refuse a yaw (profile::settingsFor).
  std::string feet_cannot_yaw;

  // estimator
  bool use_truth;         ///< control on the simulator's ground truth (diagnostics)
  double ground_height;   ///< m, terrain under the robot at start
  /// m: the terrain map agrees with the stance feet within this plus one cell (MapTerrain::
  /// checkUnderFeet); 0: not checked.
  double map_tolerance;
  estimation::EstimatorSettings estimator;
  bool use_position_fix;  ///< fuse Sensors::position_fix when the backend sends them

  // safety
  double damping;          ///< N·m·s/rad in damp
  double max_tilt;         ///< rad
  double min_base_height;  ///< m
  bool fall_on_non_foot_contact;
  double command_ttl, max_command_ttl;  ///< s
  double max_vx, max_vy, max_yaw_rate;
  double min_pose_height, max_pose_height;  ///< m
  double max_pose_tilt, max_pose_yaw;       ///< rad
  double max_push_force, max_push_duration;
  double max_plan_age;       ///< s: older plans are a planner fault
  double max_command_gap;    ///< s of wall time between command writes (real time)
  double max_late_fraction;  ///< of the last second's ticks (real time)

  // whole-body controller (stand and walk once a plan exists; the loop owns it)
  wbc::WbcSettings wbc;
  double wbc_motor_kp, wbc_motor_kd;  ///< motor PD around the WBC's targets

  // planner, telemetry
  double planner_rate;     ///< Hz
  double planner_latency;  ///< s: lockstep takes a plan this long after its input
  /// Testing, real time: the planner's thread sleeps planner_injected_stall s in its first solve
  /// from controller time planner_injected_stall_at on (0 s: never), as a planner a busy host does
  /// not run.
  double planner_injected_stall = 0.0, planner_injected_stall_at = 0.0;
  locomotion::LocomotionSettings locomotion;  ///< the planner thread copies it (MpcPlanner)
  int telemetry_decimation;
};

/// Settings as threads share them: a value nobody changes.
using SettingsPtr = std::shared_ptr<const ControlSettings>;

/// How a message names the setting at `field` (a member of s): its profile key, else `words`.
inline const char* settingName(const ControlSettings& s, const void* field, const char* words) {
  const char* key = s.key_of ? s.key_of(s, field) : nullptr;
  return key ? key : words;
}

}  // namespace ballast::control
