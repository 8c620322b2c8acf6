// The mujoco backend's profile section: every key it accepts, declared once in a table
// (mujocoSettingKeys(), mujoco_settings.cpp) with its type, default, bounds and one line of doc,
// parsed and validated by the plugins' schema engine (plugins/common/settings_schema.hpp):
// errors read `file:line:column: key: what is wrong`; unknown keys (with a "did you mean" for
// typos), keys given twice, wrong types and out-of-range values are errors.
//
// A key that means what a simbody backend key means has its name, default and bounds (sensors,
// lidar, position fixes, motors, initial state, host delays, friction, foot spheres, terrain),
// so a profile's robot is the same robot on either simulator; the contact softness and the
// stepping are MuJoCo's own (contact_*, cone, substeps, integrator, solver*).
//
// Example (every key is optional; values are the defaults unless marked):
//
//   friction: 0.8                     # Coulomb μ, robot vs terrain
//   contact_timeconst: 0.02           # s: MuJoCo solref[0]
//   substeps: 1                       # MuJoCo steps per control tick
//   motor_latency_ticks: 1            # (default 0)
//   terrain_map: maps/lab-stage.bt    # (default "": Config::terrain_map, the planner's map)
//   initial_clearance: 0.05           # (default 0) drop the robot from 5 cm
//   imu:
//     gyro_bias: 0.002                # (default 0)
//   lidar:
//     rate: 10
//
// Every key with its type, default, bounds and meaning: ballast-profile(5), section
// backend.mujoco, generated from the table (`ballastd --dump-schema=man`).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "rolling_lidar.hpp"    // plugins/common
#include "sensor_model.hpp"     // plugins/common
#include "settings_schema.hpp"  // plugins/common

namespace ballast::mujoco {

using schema::SettingsError;
using Vec3d = std::array<double, 3>;
using JointAngles = schema::NamedNumbers;

/// The parsed section. Field names are the keys with '.' replaced by '_'.
struct MujocoSettings : schema::Locations {
  double friction, contact_timeconst, contact_dampratio;
  Vec3d contact_impedance;
  std::string cone;
  double foot_sphere_radius, foot_width;
  bool body_contact;
  std::string terrain_map;
  bool floor;
  double floor_height;
  double overhang_height;

  int substeps;
  std::string integrator, solver;
  int solver_iterations;
  double solver_tolerance;
  Vec3d gravity;

  int motor_latency_ticks;
  double torque_limit_scale, joint_damping;
  bool joint_limits;
  double joint_limit_timeconst;

  double encoder_resolution, joint_velocity_noise, torque_noise;
  schema::FrameRef imu_frame;
  double imu_gyro_noise_density, imu_gyro_bias, imu_accel_noise_density, imu_accel_bias;
  double imu_orientation_noise;

  bool lidar_enabled;
  schema::FrameRef lidar_frame;
  double lidar_rate;
  int lidar_horizontal_rays, lidar_vertical_rays;
  double lidar_horizontal_fov, lidar_vertical_min, lidar_vertical_max;
  double lidar_min_range, lidar_max_range, lidar_range_noise;

  double position_fix_rate, position_fix_noise;

  std::string initial_posture;
  JointAngles initial_joints;
  Vec3d initial_xy;  ///< [2] unused
  double initial_yaw, initial_clearance;

  double host_stall_at, host_stall, host_jitter_from, host_jitter_fraction, host_jitter;
};

using SettingKey = schema::Row<MujocoSettings>;

/// The table of keys, in documentation order.
const std::vector<SettingKey>& mujocoSettingKeys();

/// Parses and validates the section; throws SettingsError "file:line:column: key: what is wrong".
MujocoSettings parseMujocoSettings(const std::string& yaml, const std::string& origin);

/// The key reference as text (the listing in this header's comment).
std::string mujocoSettingsReference();
/// BackendEntry::section_doc: this section's keys as man page entries or commented YAML.
const char* mujocoSettingsDoc(const char* format);

}  // namespace ballast::mujoco
